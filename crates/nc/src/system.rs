//! The parameters an expression reads: stored ones ([`crate::params`]) and those computed from the
//! state: LinuxCNC's `#5400`-`#5413` (tool), `#5420`-`#5428` (position), the predefined named
//! parameters (`#<_x>`, `#<_metric>`, `#<_value>` ...; `interp_namedparams.cc`); Fanuc's `#5001`...
//! (positions), `#2001`... (tool offsets), `#4001`... (modal information). A read of a value that
//! differs in the corrected program (the position, a return value, the line number) is marked.

use crate::dialect::Dialect;
use crate::expr::{Environment, ParamRef};
use crate::interpret::Exec;
use crate::modal::{FeedMode, Motion, Spindle};
use crate::tools::AXIS_LETTERS;

/// The named system parameters LinuxCNC 2.9 predefines.
pub(crate) fn is_predefined(name: &str) -> bool {
    const NAMES: [&str; 58] = [
        "_vmajor",
        "_vminor",
        "_line",
        "_motion_mode",
        "_plane",
        "_ccomp",
        "_metric",
        "_metric_machine",
        "_imperial",
        "_absolute",
        "_incremental",
        "_inverse_time",
        "_units_per_minute",
        "_units_per_rev",
        "_coord_system",
        "_tool_offset",
        "_retract_r_plane",
        "_retract_old_z",
        "_control_mode",
        "_spindle_rpm_mode",
        "_spindle_css_mode",
        "_ijk_absolute_mode",
        "_lathe_diameter_mode",
        "_lathe_radius_mode",
        "_spindle_on",
        "_spindle_cw",
        "_mist",
        "_flood",
        "_speed_override",
        "_feed_override",
        "_adaptive_feed",
        "_feed_hold",
        "_feed",
        "_rpm",
        "_current_tool",
        "_current_pocket",
        "_selected_pocket",
        "_selected_tool",
        "_x",
        "_y",
        "_z",
        "_a",
        "_b",
        "_c",
        "_u",
        "_v",
        "_w",
        "_abs_x",
        "_abs_y",
        "_abs_z",
        "_abs_a",
        "_abs_b",
        "_abs_c",
        "_value",
        "_value_returned",
        "_task",
        "_call_level",
        "_remap_level",
    ];
    NAMES.contains(&name) || name.starts_with("_ini[") || name.starts_with("_hal[")
}

impl Environment for Exec<'_> {
    fn read(&mut self, param: &ParamRef, index: Option<u32>) -> Result<f64, String> {
        match param {
            ParamRef::Named(name) => self.read_named(name),
            ParamRef::Numbered(n) => self.read_numbered(*n),
            ParamRef::Indirect(_) => self.read_numbered(index.expect("computed index")),
        }
    }

    fn exists(&self, name: &str) -> bool {
        self.params.named(name).is_some() || name.starts_with('_') && is_predefined(name)
    }
}

impl Exec<'_> {
    fn read_numbered(&mut self, n: u32) -> Result<f64, String> {
        let s = &self.state;
        match self.dialect {
            Dialect::LinuxCnc => match n {
                5420..=5428 => {
                    self.unsafe_read = true;
                    return Ok(self.state.position[(n - 5420) as usize]);
                }
                5400 => return Ok(f64::from(s.tool)),
                5401..=5409 => {
                    let k = (n - 5401) as usize;
                    return Ok(self.tools.get(s.tool).map_or(0.0, |t| t.offset[k]));
                }
                5410 => return Ok(self.tools.get(s.tool).map_or(0.0, |t| t.diameter)),
                5411..=5413 => return Ok(0.0),
                _ => {}
            },
            Dialect::Fanuc => match n {
                5001..=5008 | 5021..=5028 | 5041..=5048 | 5061..=5068 => {
                    self.unsafe_read = true;
                    // axis 1, 2, 3, 4 ... = X Y Z A ...
                    let k = ((n - 1) % 20) as usize;
                    return Ok(match n {
                        5021..=5028 => self.state.frame.external(&self.state.position)[k],
                        _ => self.state.position[k],
                    });
                }
                2001..=2400 | 10001..=13999 => {
                    let h = if n <= 2400 { n - 2000 } else { n - 10000 };
                    return Ok(self.tools.get(h).map_or(0.0, |t| t.offset[2]));
                }
                4001..=4130 | 4201..=4330 => return Ok(self.fanuc_modal(if n > 4200 { n - 200 } else { n })),
                // the part counts: 0 at the start (not known here), then what the program wrote
                3901 | 3902 => return Ok(self.params.numbered(n).filter(|v| !v.is_nan()).unwrap_or(0.0)),
                0 => return Ok(f64::NAN),
                n if !self.params.holds(n) || (1000..2001).contains(&n) || (2401..5201).contains(&n) => {
                    return Err(format!("system variable #{n} is not supported by this corrector"))
                }
                _ => {}
            },
        }
        self.params.numbered(n).ok_or_else(|| format!("parameter #{n} does not exist"))
    }

    /// Fanuc `#4001`-`#4130` (and `#4201`-`#4330`, the same for the block being executed): the
    /// modal G codes of the groups, F S T.
    fn fanuc_modal(&self, n: u32) -> f64 {
        let s = &self.state;
        match n {
            4001 => match s.motion {
                Motion::Rapid => 0.0,
                Motion::Feed => 1.0,
                Motion::Arc { clockwise: true } => 2.0,
                Motion::Arc { clockwise: false } => 3.0,
                _ => 1.0,
            },
            4002 => s.plane.gcode(),
            4003 => {
                if s.frame.incremental {
                    91.0
                } else {
                    90.0
                }
            }
            4005 => match s.feed_mode {
                FeedMode::PerRevolution => 95.0,
                _ => 94.0,
            },
            4006 => {
                if s.frame.inch {
                    20.0
                } else {
                    21.0
                }
            }
            4007 => 40.0,
            4008 => {
                if s.tool_offset_on {
                    43.0
                } else {
                    49.0
                }
            }
            4009 => match s.motion {
                Motion::Cycle(c) => f64::from(c) / 10.0,
                _ => 80.0,
            },
            4010 => {
                if s.retract_to_r {
                    99.0
                } else {
                    98.0
                }
            }
            4014 => 53.0 + f64::from(s.frame.system.min(6)),
            4109 => s.feed,
            4119 => s.speed,
            4120 => f64::from(s.tool),
            _ => 0.0,
        }
    }

    fn read_named(&mut self, name: &str) -> Result<f64, String> {
        if let Some(v) = self.params.named(name) {
            return Ok(v);
        }
        if !name.starts_with('_') || self.dialect == Dialect::Fanuc {
            return Err(format!("named parameter #<{name}> is not defined"));
        }
        let s = &self.state;
        let flag = |c: bool| f64::from(u8::from(c));
        let position = |k: usize| s.position[k];
        Ok(match name {
            "_vmajor" => 2.0,
            "_vminor" => 9.0,
            "_line" => {
                self.unsafe_read = true;
                self.line_number as f64
            }
            "_motion_mode" => match s.motion {
                Motion::None => 800.0,
                Motion::Rapid => 0.0,
                Motion::Feed => 10.0,
                Motion::Arc { clockwise: true } => 20.0,
                Motion::Arc { clockwise: false } => 30.0,
                Motion::Cycle(c) | Motion::Spline(c) => f64::from(c),
            },
            "_plane" => s.plane.gcode() * 10.0,
            "_ccomp" => 400.0,
            "_metric" => flag(!s.frame.inch),
            "_metric_machine" => flag(!self.machine_inch),
            "_imperial" => flag(s.frame.inch),
            "_absolute" => flag(!s.frame.incremental),
            "_incremental" => flag(s.frame.incremental),
            "_inverse_time" => flag(s.feed_mode == FeedMode::InverseTime),
            "_units_per_minute" => flag(s.feed_mode == FeedMode::PerMinute),
            "_units_per_rev" => flag(s.feed_mode == FeedMode::PerRevolution),
            "_coord_system" => {
                let o = f64::from(s.frame.system);
                if o < 7.0 {
                    530.0 + 10.0 * o
                } else {
                    584.0 + o
                }
            }
            "_tool_offset" => flag(s.frame.tool.iter().any(|&v| v != 0.0)),
            "_retract_r_plane" => flag(s.retract_to_r),
            "_retract_old_z" => flag(!s.retract_to_r),
            "_control_mode" => f64::from(s.path_mode) / 10.0,
            "_spindle_rpm_mode" => flag(!s.css),
            "_spindle_css_mode" => flag(s.css),
            "_ijk_absolute_mode" => flag(s.frame.ijk_absolute),
            "_lathe_diameter_mode" => flag(s.frame.diameter),
            "_lathe_radius_mode" => flag(!s.frame.diameter),
            "_spindle_on" => flag(s.spindle != Spindle::Stopped),
            "_spindle_cw" => flag(s.spindle == Spindle::Clockwise),
            "_mist" => flag(s.mist),
            "_flood" => flag(s.flood),
            "_speed_override" | "_feed_override" => 1.0,
            "_adaptive_feed" | "_feed_hold" | "_task" | "_remap_level" => 0.0,
            "_feed" => s.feed,
            "_rpm" => s.speed.abs(),
            "_current_tool" => f64::from(s.tool),
            "_selected_tool" => s.selected_tool.map_or(-1.0, f64::from),
            "_current_pocket" | "_selected_pocket" => 0.0,
            "_x" | "_y" | "_z" | "_a" | "_b" | "_c" | "_u" | "_v" | "_w" => {
                self.unsafe_read = true;
                position(AXIS_LETTERS.iter().position(|&l| l.to_ascii_lowercase() == name.as_bytes()[1]).expect("an axis"))
            }
            "_abs_x" | "_abs_y" | "_abs_z" | "_abs_a" | "_abs_b" | "_abs_c" => {
                self.unsafe_read = true;
                let k = AXIS_LETTERS.iter().position(|&l| l.to_ascii_lowercase() == name.as_bytes()[5]).expect("an axis");
                s.frame.external(&s.position)[k]
            }
            "_value" => {
                self.unsafe_read = true;
                self.return_value
            }
            "_value_returned" => {
                self.unsafe_read = true;
                flag(self.value_returned)
            }
            "_call_level" => self.calls.len() as f64,
            n if n.starts_with("_ini[") || n.starts_with("_hal[") => {
                return Err(format!("#<{n}> reads the machine's INI file or HAL, which this corrector does not have"))
            }
            n => return Err(format!("named parameter #<{n}> is not defined")),
        })
    }
}
