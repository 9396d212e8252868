//! How a post-processor writes words: the number format (fixed digits `5.0000`, trimmed `5.`,
//! trimmed `5`), the separator between words, sequence numbers, modal suppression of the motion
//! code and of unchanged axes, and the part geometry every style cuts, in program units (mm, or
//! inch when the part says so): a rounded-rectangle contour in depth passes (arcs as I J or R), a
//! zig-zag facing pass, and holes as canned cycles or as plain moves (for posts of controllers
//! without cycles).

/// The number format of a post.
#[derive(Clone, Copy)]
pub enum Digits {
    /// Always `n` decimals (`5.0000`, CamBam `3.0` with 1 at least is `Trim` with point).
    Fixed(usize),
    /// At most `n` decimals, trailing zeros dropped; `point`: a whole number keeps its `.` (Fanuc).
    Trim(usize, bool),
}

/// Arc centre words.
#[derive(Clone, Copy, PartialEq)]
pub enum ArcWords {
    Ij,
    R,
    /// SINUMERIK `CR=`.
    Cr,
}

/// A canned cycle of the hole pattern.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Cycle {
    Drill,
    Peck,
    ChipBreak,
    Tap,
    Bore,
}

impl Cycle {
    pub fn code(self) -> &'static str {
        match self {
            Cycle::Drill => "G81",
            Cycle::Peck => "G83",
            Cycle::ChipBreak => "G73",
            Cycle::Tap => "G84",
            Cycle::Bore => "G85",
        }
    }
}

/// A part: where it lies, its size, depth passes, holes; the variant `k` of a style.
#[derive(Clone, Debug)]
pub struct Part {
    pub inch: bool,
    pub x0: f64,
    pub y0: f64,
    pub w: f64,
    pub h: f64,
    pub r: f64,
    pub depth: f64,
    pub passes: usize,
    pub clear: f64,
    pub safe: f64,
    pub feed: f64,
    pub plunge: f64,
    pub spindle: u32,
    pub holes: Vec<[f64; 2]>,
    pub hole_depth: f64,
    pub peck: f64,
    pub cycle: Cycle,
}

impl Part {
    /// Variant `k` (0, 1, ...), in mm or in inch (every length divided by 25.4 and rounded to
    /// 0.0001 in, as a designer in inch would dimension it).
    pub fn new(k: usize, inch: bool) -> Part {
        let u = k as f64;
        let s = |mm: f64| if inch { (mm / 25.4 * 1e4).round() / 1e4 } else { mm };
        let holes = (0..2 + k % 4).map(|i| [s(-40.0 + 7.0 * u + 11.0 * i as f64), s(-30.0 + 3.0 * u - 6.0 * i as f64)]).collect();
        Part {
            inch,
            x0: s(-50.0 + 9.0 * u),
            y0: s(-35.0 + 4.0 * u),
            w: s(40.0 + 13.0 * u),
            h: s(25.0 + 7.0 * u),
            r: s(3.0 + (k % 4) as f64),
            depth: s(1.5 + 0.5 * (k % 3) as f64),
            passes: 1 + k % 3,
            clear: s(15.0),
            safe: s(5.0),
            feed: if inch { 40.0 } else { 1000.0 + 50.0 * u },
            plunge: if inch { 12.0 } else { 300.0 },
            spindle: 6000 + 500 * k as u32,
            holes,
            hole_depth: s(6.0 + (k % 5) as f64),
            peck: s(1.5),
            cycle: [Cycle::Drill, Cycle::Peck, Cycle::ChipBreak, Cycle::Tap, Cycle::Bore][k % 5],
        }
    }
}

/// A post's writer.
pub struct W {
    pub out: String,
    pub digits: Digits,
    pub sep: &'static str,
    /// Next sequence number and step (none: no N words).
    pub seq: Option<(u32, u32)>,
    /// Write the motion code only when it changes.
    pub modal_g: bool,
    /// Write only the axes that change.
    pub modal_axes: bool,
    /// `F` before the axis words (CamBam).
    pub feed_first: bool,
    pub arcs: ArcWords,
    /// Prefix of a line without a motion code (SketchUcam's indent).
    pub indent: &'static str,
    g: Option<u8>,
    pos: [Option<f64>; 3],
    f: Option<f64>,
}

impl W {
    pub fn new(digits: Digits, sep: &'static str) -> W {
        W {
            out: String::new(),
            digits,
            sep,
            seq: None,
            modal_g: true,
            modal_axes: true,
            feed_first: false,
            arcs: ArcWords::Ij,
            indent: "",
            g: None,
            pos: [None; 3],
            f: None,
        }
    }

    pub fn num(&self, v: f64) -> String {
        let mut s = match self.digits {
            Digits::Fixed(n) => format!("{v:.n$}"),
            Digits::Trim(n, point) => {
                let mut s = format!("{v:.n$}");
                if s.contains('.') {
                    s = s.trim_end_matches('0').to_string();
                    if !point {
                        s = s.trim_end_matches('.').to_string();
                    }
                }
                s
            }
        };
        if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') && s.starts_with('-') {
            s.remove(0);
        }
        s
    }

    /// A block (with its sequence number).
    pub fn line(&mut self, text: &str) {
        if let Some((n, step)) = self.seq {
            self.out.push_str(&format!("N{n}{}", self.sep));
            self.seq = Some((n + step, step));
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    /// Lines without sequence numbers (comments, `%`).
    pub fn raw(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push('\n');
    }

    /// Forget the modal state (after a tool change, a reference return or a cycle).
    pub fn reset(&mut self) {
        self.g = None;
        self.pos = [None; 3];
    }

    /// A motion block: `g` 0-3, the axes that are given, arc words, the feed.
    pub fn motion(&mut self, g: u8, p: [Option<f64>; 3], arc: &str, feed: Option<f64>) {
        let mut words = Vec::new();
        if !self.modal_g || self.g != Some(g) {
            words.push(format!("G{g}"));
        }
        let f = feed.filter(|f| self.f != Some(*f)).map(|f| format!("F{}", self.num(f)));
        if self.feed_first {
            words.extend(f.clone());
        }
        for (k, l) in ["X", "Y", "Z"].iter().enumerate() {
            if let Some(v) = p[k] {
                if !self.modal_axes || self.pos[k] != Some(v) || !arc.is_empty() && k < 2 {
                    words.push(format!("{l}{}", self.num(v)));
                }
                self.pos[k] = Some(v);
            }
        }
        if !arc.is_empty() {
            words.push(arc.to_string());
        }
        if !self.feed_first {
            words.extend(f);
        }
        if let Some(v) = feed {
            self.f = Some(v);
        }
        if words.is_empty() {
            return;
        }
        let text = words.join(self.sep);
        let text = if self.g == Some(g) && !text.starts_with('G') { format!("{}{text}", self.indent) } else { text };
        self.g = Some(g);
        self.line(&text);
    }

    pub fn rapid(&mut self, x: Option<f64>, y: Option<f64>, z: Option<f64>) {
        self.motion(0, [x, y, z], "", None);
    }

    pub fn feed(&mut self, x: Option<f64>, y: Option<f64>, z: Option<f64>, f: f64) {
        self.motion(1, [x, y, z], "", Some(f));
    }

    /// An XY arc from the current point to (x, y) around centre (cx, cy).
    pub fn arc(&mut self, cw: bool, x: f64, y: f64, c: [f64; 2], f: f64) {
        let (px, py) = (self.pos[0].unwrap(), self.pos[1].unwrap());
        let words = match self.arcs {
            ArcWords::Ij => format!("I{}{}J{}", self.num(c[0] - px), self.sep, self.num(c[1] - py)),
            ArcWords::R => format!("R{}", self.num((c[0] - px).hypot(c[1] - py))),
            ArcWords::Cr => format!("CR={}", self.num((c[0] - px).hypot(c[1] - py))),
        };
        self.motion(if cw { 2 } else { 3 }, [Some(x), Some(y), None], &words, Some(f));
    }

    /// The rounded-rectangle contour in depth passes, counterclockwise from the middle of the
    /// bottom edge, each pass entered with a feed plunge.
    pub fn contour(&mut self, p: &Part) {
        let (x0, y0, x1, y1, r) = (p.x0, p.y0, p.x0 + p.w, p.y0 + p.h, p.r);
        let xm = p.x0 + p.w / 2.0;
        self.rapid(Some(xm), Some(y0), None);
        self.rapid(None, None, Some(p.safe));
        for pass in 1..=p.passes {
            let z = -p.depth * pass as f64 / p.passes as f64;
            let z = (z * 1e4).round() / 1e4;
            self.feed(None, None, Some(z), p.plunge);
            self.feed(Some(x1 - r), Some(y0), None, p.feed);
            self.arc(false, x1, y0 + r, [x1 - r, y0 + r], p.feed);
            self.feed(Some(x1), Some(y1 - r), None, p.feed);
            self.arc(false, x1 - r, y1, [x1 - r, y1 - r], p.feed);
            self.feed(Some(x0 + r), Some(y1), None, p.feed);
            self.arc(false, x0, y1 - r, [x0 + r, y1 - r], p.feed);
            self.feed(Some(x0), Some(y0 + r), None, p.feed);
            self.arc(false, x0 + r, y0, [x0 + r, y0 + r], p.feed);
            self.feed(Some(xm), Some(y0), None, p.feed);
        }
        self.rapid(None, None, Some(p.clear));
    }

    /// A zig-zag facing pass over the part at Z 0 (rows 1/4 of the height apart).
    pub fn facing(&mut self, p: &Part) {
        let rows = 5;
        self.rapid(Some(p.x0), Some(p.y0), None);
        self.rapid(None, None, Some(p.safe));
        self.feed(None, None, Some(0.0), p.plunge);
        for i in 0..rows {
            let y = p.y0 + p.h * i as f64 / (rows - 1) as f64;
            let y = (y * 1e4).round() / 1e4;
            let x = if i % 2 == 0 { p.x0 + p.w } else { p.x0 };
            if i > 0 {
                self.feed(None, Some(y), None, p.feed);
            }
            self.feed(Some(x), None, None, p.feed);
        }
        self.rapid(None, None, Some(p.clear));
    }

    /// The holes as a canned cycle (`G98`/`G99` as given, Q for the pecking cycles, F for
    /// tapping the pitch times the speed), then `G80`.
    pub fn cycle(&mut self, p: &Part, retract: &str, cycle: Cycle) {
        let f = if cycle == Cycle::Tap {
            if p.inch {
                p.spindle as f64 / 20.0 / 10.0
            } else {
                1.25 * 400.0
            }
        } else {
            p.plunge
        };
        let first = p.holes[0];
        self.rapid(Some(first[0]), Some(first[1]), None);
        self.rapid(None, None, Some(p.clear));
        let mut words = vec![format!("{retract}{}{}", self.sep, cycle.code())];
        words.push(format!("X{}{}Y{}", self.num(first[0]), self.sep, self.num(first[1])));
        words.push(format!("Z{}{}R{}", self.num(-p.hole_depth), self.sep, self.num(p.safe)));
        if matches!(cycle, Cycle::Peck | Cycle::ChipBreak) {
            words.push(format!("Q{}", self.num(p.peck)));
        }
        words.push(format!("F{}", self.num(f)));
        self.line(&words.join(self.sep));
        for h in &p.holes[1..] {
            let mut w = Vec::new();
            if h[0] != first[0] {
                w.push(format!("X{}", self.num(h[0])));
            }
            w.push(format!("Y{}", self.num(h[1])));
            self.line(&w.join(self.sep));
        }
        self.line("G80");
        self.reset();
        self.f = None;
        self.rapid(None, None, Some(p.clear));
    }

    /// The holes as plain moves: rapid above, feed to the bottom (in steps of the peck depth),
    /// rapid out.
    pub fn holes_expanded(&mut self, p: &Part) {
        for h in &p.holes {
            self.rapid(Some(h[0]), Some(h[1]), None);
            self.rapid(None, None, Some(p.safe));
            let mut z = 0.0;
            while z > -p.hole_depth + 1e-9 {
                z = (z - p.peck).max(-p.hole_depth);
                let zz = (z * 1e4).round() / 1e4;
                self.feed(None, None, Some(zz), p.plunge);
                self.rapid(None, None, Some(p.safe));
            }
        }
        self.rapid(None, None, Some(p.clear));
    }
}
