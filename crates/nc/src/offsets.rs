//! Commands that change where program coordinates are on the machine: the coordinate system
//! (`G54`-`G59.3`, Fanuc `G54.1 P`), tool length offsets (`G43`, `G43.1`, `G43.2`, Fanuc `G44`,
//! `G49`), `G10` (work offsets L2/L20, tool table L1, Fanuc L10-L13), `G92`/`G92.1`-`G92.3`/`G52`,
//! and rs274's reading of the position after a tool change. As LinuxCNC 2.9 does them
//! (`interp_convert.cc`: `convert_coordinate_system`, `convert_tool_length_offset`,
//! `convert_setup`, `convert_axis_offsets`); the program position is kept at the same machine
//! position when an offset changes, except a Fanuc's tool length offset, which the controller
//! applies by moving with the next move (the behaviour with the Fanuc parameter TOS, No. 5006#6,
//! at 0, as secondary sources describe it; not read in the operator's manual here): its program
//! position stays. Where the axis moves in between, the end of the next move is the same.

use crate::dialect::Dialect;
use crate::dialects::gcode_text;
use crate::execute::Words;
use crate::interpret::Exec;
use crate::modal::AXES;
use crate::tools::AXIS_LETTERS;
use crate::trace::Relative;

impl Exec<'_> {
    /// rs274 after a tool change: the program position of the last move with the tool offset of
    /// that move; the controller believes the machine moved by the change of offset.
    pub(crate) fn rs274_resync(&mut self, step: usize) {
        let frame = self.state.frame;
        let external = frame.external(&self.state.position);
        let mut then = frame;
        then.tool = frame.from_mm(&self.tool_at_last_move);
        let position = then.program(&external);
        let before = self.position;
        self.state.position = position;
        self.position = self.program_to_machine(&position);
        let jump: crate::trace::Axes = std::array::from_fn(|i| self.position[i] - before[i]);
        if jump.iter().any(|&d| d != 0.0) {
            self.trace.steps[step].jump = Some(jump);
        }
    }

    /// `G54`-`G59.3`, `G54.1 P`: the work offsets of `system`.
    pub(crate) fn select_system(&mut self, system: u8) -> Result<(), String> {
        if system == self.state.frame.system {
            return Ok(());
        }
        let old = self.state.frame;
        self.state.frame.system = system;
        self.state.frame.g5x = self.system_offsets(system)?;
        if self.dialect == Dialect::LinuxCnc {
            self.state.frame.rotation = self.params.numbered(5210 + 20 * u32::from(system)).unwrap_or(0.0);
            self.params.set_numbered(5220, f64::from(system))?;
        }
        self.refresh_position(&old);
        Ok(())
    }

    /// `G43 H`, `G43` (the spindle's tool), `G43.1` (axis words), `G43.2` (added), Fanuc `G44`,
    /// `G49`: the tool offset, the program position kept at the same machine position.
    pub(crate) fn tool_length(&mut self, code: u16, w: &mut Words) -> Result<(), String> {
        let fanuc = self.dialect == Dialect::Fanuc;
        let mut offset = self.state.frame.tool;
        let from_table = |exec: &mut Self, n: u32| -> Result<[f64; AXES], String> {
            if n == 0 {
                return Ok([0.0; AXES]);
            }
            let tool = exec.tool_entry(n)?;
            let wear = exec.wear.iter().find(|(h, _)| *h == n).map_or(0.0, |(_, v)| *v);
            Ok(std::array::from_fn(|k| {
                if fanuc && k != 2 {
                    0.0
                } else {
                    exec.user_to_program(k, tool.offset[k] + if k == 2 { wear } else { 0.0 })
                }
            }))
        };
        match code {
            490 => {
                offset = [0.0; AXES];
                self.state.tool_offset_on = false;
            }
            430 | 440 => {
                let h = w.take(b'H');
                let n = match h {
                    Some(h) if h < 0.0 || h.fract() != 0.0 => return Err(format!("H{h} is not an offset number")),
                    Some(h) => h as u32,
                    None if fanuc => return Err("G43 needs the offset number H".into()),
                    None => self.state.tool,
                };
                offset = from_table(self, n)?;
                if code == 440 {
                    offset = offset.map(|v| -v);
                }
                self.state.tool_offset_on = true;
                self.setup_words.push((b'G', f64::from(code) / 10.0));
                if let Some(h) = h {
                    self.setup_words.push((b'H', h));
                }
            }
            431 | 432 => {
                if code == 432 {
                    if let Some(h) = w.take(b'H') {
                        let add = from_table(self, h as u32)?;
                        for k in 0..AXES {
                            offset[k] += add[k];
                        }
                    }
                }
                for (k, &l) in AXIS_LETTERS.iter().enumerate() {
                    if let Some(v) = w.take(l) {
                        offset[k] = if code == 432 { offset[k] + v } else { v };
                    }
                }
                self.state.tool_offset_on = true;
                // an expanded copy writes the resulting offsets with G43.1
                self.setting_words.push((b'G', 43.1));
                for (k, &l) in AXIS_LETTERS.iter().enumerate() {
                    if offset[k] != 0.0 || self.state.frame.tool[k] != 0.0 {
                        self.setting_words.push((l, offset[k]));
                    }
                }
            }
            _ => unreachable!("tool length code"),
        }
        if code == 490 {
            self.setup_words.push((b'G', 49.0));
        }
        let old = self.state.frame;
        self.state.frame.tool = offset;
        if fanuc {
            // the program position stays: the next move takes the machine to it with the new offset
            let held = old.held_tool.unwrap_or(old.tool);
            self.state.frame.held_tool = (held != offset).then_some(held);
        } else {
            self.refresh_position(&old);
        }
        Ok(())
    }

    /// `G10 L1/L2/L20` (LinuxCNC), `G10 L2/L20/L10/L11` (Fanuc work and tool offsets).
    pub(crate) fn g10(&mut self, w: &mut Words, step: usize) -> Result<(), String> {
        let l = w.take(b'L').ok_or("G10 needs L")?;
        let p = w.take(b'P');
        let fanuc = self.dialect == Dialect::Fanuc;
        self.setting_words.push((b'G', 10.0));
        self.setting_words.push((b'L', l));
        if let Some(p) = p {
            self.setting_words.push((b'P', p));
        }
        let (axes, _) = w.axes();
        let l = l.round() as u32;
        match (self.dialect, l) {
            (_, 2) | (Dialect::LinuxCnc, 20) | (Dialect::Fanuc, 20) => {
                let p = p.ok_or("G10 L2/L20 needs the coordinate system P")?;
                let system = match (self.dialect, l) {
                    (Dialect::Fanuc, 20) => {
                        if !(1.0..=48.0).contains(&p) {
                            return Err(format!("G10 L20 P{p}: P must be 1 to 48 (G54.1 P1-P48)"));
                        }
                        10 + p as u8 - 1
                    }
                    (Dialect::Fanuc, _) if p == 0.0 => 0,
                    _ if p == 0.0 => self.state.frame.system,
                    _ if (1.0..=9.0).contains(&p) && p.fract() == 0.0 && (!fanuc || p <= 6.0) => p as u8,
                    _ => return Err(format!("G10 L{l} P{p}: P must be a coordinate system, 1 to {}", if fanuc { 6 } else { 9 })),
                };
                let relative_to_position = self.dialect == Dialect::LinuxCnc && l == 20;
                let base = if system == 0 { 5201 } else { self.system_base(system) };
                let rotation_param = 5210 + 20 * u32::from(system);
                if let Some(r) = w.take(b'R') {
                    if fanuc || relative_to_position {
                        return Err("R (rotation) only with LinuxCNC G10 L2".into());
                    }
                    self.params.set_numbered(rotation_param, r)?;
                    self.setting_words.push((b'R', r));
                }
                let r = if fanuc { 0.0 } else { self.params.numbered(rotation_param).unwrap_or(0.0) };
                let mut current_in_system = [0.0; AXES];
                if relative_to_position {
                    self.trace.steps[step].relative = Some((Relative::G10L20 { system, rotation: r }, self.position));
                    // the current point in the coordinates of `system` (its offsets and rotation)
                    let mut frame = self.state.frame;
                    frame.g5x = self.system_offsets(system)?;
                    frame.rotation = r;
                    current_in_system = frame.program(&self.state.frame.external(&self.state.position));
                }
                let old = |exec: &Self, k: usize| {
                    exec.user_to_program(k, exec.params.numbered(base + k as u32).filter(|v| !v.is_nan()).unwrap_or(0.0))
                };
                let mut new: [f64; AXES] = std::array::from_fn(|k| old(self, k));
                if relative_to_position {
                    // LinuxCNC convert_setup: X and Y through the system's rotation
                    let rot = |x: f64, y: f64| {
                        let (s, c) = r.to_radians().sin_cos();
                        (x * c - y * s, x * s + y * c)
                    };
                    if axes[0].is_some() || axes[1].is_some() {
                        let (cx, cy) = (current_in_system[0], current_in_system[1]);
                        let (x, y) = (axes[0].unwrap_or(cx), axes[1].unwrap_or(cy));
                        let (ox, oy) = rot(cx, cy);
                        let (nx, ny) = rot(x, y);
                        new[0] = ox + old(self, 0) - nx;
                        new[1] = oy + old(self, 1) - ny;
                    }
                    for k in 2..AXES {
                        if let Some(v) = axes[k] {
                            new[k] = current_in_system[k] + old(self, k) - v;
                        }
                    }
                } else {
                    for k in 0..AXES {
                        if let Some(v) = axes[k] {
                            new[k] = if fanuc && self.state.frame.incremental { new[k] + v } else { v };
                        }
                    }
                }
                for k in 0..AXES {
                    if let Some(v) = axes[k] {
                        self.setting_words.push((AXIS_LETTERS[k], v));
                    }
                    if axes[k].is_some() || relative_to_position && k < 2 && (axes[0].is_some() || axes[1].is_some()) {
                        let user = self.program_to_user(k, new[k]);
                        self.params.set_numbered(base + k as u32, user)?;
                    }
                }
                w.use_axes();
                let active = system == self.state.frame.system || fanuc && system == 0;
                if active {
                    let before = self.state.frame;
                    self.state.frame.g5x = self.system_offsets(self.state.frame.system)?;
                    if !fanuc {
                        self.state.frame.rotation = r;
                    }
                    self.refresh_position(&before);
                }
            }
            (Dialect::LinuxCnc, 1) => {
                let p = p.ok_or("G10 L1 needs the tool number P")?;
                let tool = self.tools.get(p as u32).ok_or_else(|| format!("G10 L1: tool {p} is not in the tool table"))?.clone();
                let mut values = tool.offset;
                for (k, &letter) in AXIS_LETTERS.iter().enumerate() {
                    if let Some(v) = w.take(letter) {
                        values[k] = self.program_to_user(k, v);
                        self.setting_words.push((letter, v));
                    }
                }
                if let Some(r) = w.take(b'R') {
                    self.setting_words.push((b'R', r));
                    self.tools.entry(p as u32).diameter = 2.0 * self.program_to_user(0, r);
                }
                for l in [b'I', b'J', b'Q'] {
                    if let Some(v) = w.take(l) {
                        self.setting_words.push((l, v));
                    }
                }
                self.tools.entry(p as u32).offset = values;
            }
            (Dialect::Fanuc, 10 | 11) => {
                let p = p.ok_or("G10 L10/L11 needs the offset number P")?;
                let r = w.take(b'R').ok_or("G10 L10/L11 needs the offset value R")?;
                self.setting_words.push((b'R', r));
                let user = self.program_to_user(2, r);
                let n = p as u32;
                if l == 10 {
                    let e = self.tools.entry(n);
                    e.offset[2] = if self.state.frame.incremental { e.offset[2] + user } else { user };
                } else {
                    let old = self.wear.iter().find(|(h, _)| *h == n).map_or(0.0, |(_, v)| *v);
                    let v = if self.state.frame.incremental { old + user } else { user };
                    self.wear.retain(|(h, _)| *h != n);
                    self.wear.push((n, v));
                }
            }
            (Dialect::Fanuc, 12 | 13) => {
                // cutter radius offsets: no effect without G41/G42, which are refused
                if let Some(r) = w.take(b'R') {
                    self.setting_words.push((b'R', r));
                }
            }
            (_, l) => return Err(format!("G10 L{l} is not supported (LinuxCNC: L1 L2 L20; Fanuc: L2 L20 L10-L13)")),
        }
        Ok(())
    }

    /// `G92`, `G92.1`-`G92.3`, `G52`.
    pub(crate) fn g92(&mut self, code: u16, w: &mut Words, step: usize) -> Result<(), String> {
        let (axes, any) = w.axes();
        let old = self.state.frame;
        let p = &mut self.state;
        self.setting_words.push((b'G', f64::from(code) / 10.0));
        match code {
            920 | 520 => {
                if !any {
                    return Err(format!("G{} needs axis words", gcode_text(code)));
                }
                if code == 920 {
                    self.trace.steps[step].relative = Some((Relative::G92, self.position));
                }
                for k in 0..AXES {
                    if let Some(v) = axes[k] {
                        if code == 920 {
                            p.frame.g92[k] = p.position[k] + p.frame.g92[k] - v;
                            p.position[k] = v;
                        } else {
                            p.position[k] += p.frame.g92[k] - v;
                            p.frame.g92[k] = v;
                        }
                        self.setting_words.push((AXIS_LETTERS[k], v));
                    }
                }
                w.use_axes();
                self.state.g92_applied = true;
                if self.dialect == Dialect::LinuxCnc {
                    self.params.set_numbered(5210, 1.0)?;
                    for k in 0..AXES {
                        let v = self.program_to_user(k, self.state.frame.g92[k]);
                        self.params.set_numbered(5211 + k as u32, v)?;
                    }
                }
                return Ok(());
            }
            921 | 922 => {
                for k in 0..AXES {
                    p.position[k] += p.frame.g92[k];
                    p.frame.g92[k] = 0.0;
                }
                p.g92_applied = false;
                if self.dialect == Dialect::LinuxCnc {
                    self.params.set_numbered(5210, 0.0)?;
                    if code == 921 {
                        for k in 0..AXES {
                            self.params.set_numbered(5211 + k as u32, 0.0)?;
                        }
                    }
                }
            }
            _ => {
                let g92: [f64; AXES] =
                    std::array::from_fn(|k| self.user_to_program(k, self.params.numbered(5211 + k as u32).unwrap_or(0.0)));
                self.state.frame.g92 = g92;
                self.state.g92_applied = true;
                self.params.set_numbered(5210, 1.0)?;
                self.refresh_position(&old);
            }
        }
        Ok(())
    }
}
