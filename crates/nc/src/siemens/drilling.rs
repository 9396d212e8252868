//! The values of a SINUMERIK drilling cycle and the moves it makes along the tool axis (Z in G17,
//! program units), from the parameter lists of SINUMERIK 840D/840Di/810D Programming Guide Cycles
//! (09.2001 to 03.2004 editions: "Drilling, centering - CYCLE81", "Drilling, counterboring -
//! CYCLE82", "Deep-hole drilling - CYCLE83") and their 840D sl successors (Programming Manual Job
//! Planning, the trailing `_AXN, _MDEP, _VRT, _DTD, _DIS1` and the mode parameters):
//!
//! - every cycle: `G0` to the reference plane plus the safety distance, RFP + SDIS; the final
//!   depth DP (absolute), or RFP - DPR when DPR (relative to RFP, without sign) is given, which
//!   then counts; at the end `G0` to the retraction plane RTP;
//! - CYCLE81: `G1` to the depth; CYCLE82: `G1` to the depth and the dwell DTB (s) there;
//! - CYCLE83 (deep-hole drilling): infeeds of `G1` to the drilling depths `d_k = RFP - k f`, where
//!   `f = RFP - FDEP` (or FDPR, relative to RFP) is the first infeed, while `d_k` is above the
//!   final depth, the last infeed to the final depth. Between infeeds, with chip breaking
//!   (VARI 0) a `G1` back by the retraction distance `_VRT` (1 mm when 0 or empty) and the next
//!   infeed from there; with swarf removal (VARI 1) a `G0` out to RFP + SDIS, the dwell DTS there,
//!   a `G0` back to the last depth plus the anticipation distance `_DIS1`, and the next infeed
//!   from there. DTB dwells at each drilling depth, `_DTD` at the final depth (DTB there when
//!   `_DTD` is 0).
//!
//! What is read and what is refused: the degression DAM must be 0 (every infeed the first one's,
//! as the Autodesk 840D post writes Fusion's constant peck: FDEP = RFP - peck, DAM 0; a DAM other
//! than 0 shortens the infeeds by a rule whose last strokes were not confirmed from a published
//! copy of the manual); swarf removal needs its anticipation distance `_DIS1` (0 or empty lets
//! the cycle compute it, by a rule not confirmed either); `_MDEP` (the minimum infeed, used with
//! degression only) is passed over; `_AXN` must be empty, 0 or 3 (Z); the mode parameters
//! `_GMODE`, `_AMODE` empty or 0; dwells in revolutions (negative) are refused.

use crate::cycles::pecks;
use crate::modal::MM_PER_INCH;

/// The deep-hole drilling of a CYCLE83.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pecking {
    /// The first infeed from RFP (program units, positive), and whether it was given as FDPR.
    pub infeed: f64,
    pub relative: bool,
    /// Swarf removal (VARI 1): out to RFP + SDIS between infeeds; chip breaking (VARI 0): back
    /// by `back`.
    pub swarf: bool,
    /// Chip breaking: the retraction `_VRT`; swarf removal: the anticipation distance `_DIS1`.
    pub back: f64,
    /// Dwells (s) at each drilling depth (DTB) and at RFP + SDIS after a swarf removal (DTS).
    pub dwell_each: f64,
    pub dwell_start: f64,
}

/// A drilling cycle's values (program units, along Z).
#[derive(Clone, Debug, PartialEq)]
pub struct Drilling {
    pub number: u16,
    /// Retraction plane RTP, reference plane RFP, safety distance SDIS (without sign), final depth.
    pub rtp: f64,
    pub rfp: f64,
    pub sdis: f64,
    pub depth: f64,
    /// The depth was given as DPR (relative to RFP).
    pub relative: bool,
    /// Dwell at the final depth (s).
    pub dwell: f64,
    pub pecking: Option<Pecking>,
    /// The call as written, from `MCALL` or `CYCLE` to its `)`.
    pub call: String,
}

/// One move (or dwell) of a cycle after its positioning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stroke {
    Rapid(f64),
    Feed(f64),
    Dwell(f64),
}

/// Parameter positions (0-based) of CYCLE83: FDEP, FDPR, DAM, DTB, DTS, FRF, VARI, _AXN, _MDEP,
/// _VRT, _DTD, _DIS1.
const FDEP: usize = 5;
const VARI: usize = 11;
const VRT: usize = 14;
const DIS1: usize = 16;

impl Drilling {
    /// The parameter count before the 840D sl's mode parameters `_GMODE, _DMODE, _AMODE`.
    pub fn parameters(number: u16) -> usize {
        match number {
            81 => 5,
            82 => 6,
            _ => 17,
        }
    }

    /// From the values of `CYCLE<number>(...)` (empty: `None`), in a program in `inch`.
    pub(crate) fn of(number: u16, v: &[Option<f64>], inch: bool, call: String) -> Result<Drilling, String> {
        let name = format!("CYCLE{number}");
        let modes = Self::parameters(number);
        if v.len() > modes + 3 {
            return Err(format!("{name} takes {} parameters, not {}", modes + 3, v.len()));
        }
        let get = |k: usize| v.get(k).copied().flatten();
        for (k, mode) in [(modes, "_GMODE"), (modes + 2, "_AMODE")] {
            if let Some(m) = get(k).filter(|&m| m != 0.0) {
                return Err(format!("{name}: {mode} {m} (a mode of the 840D sl's cycle) is not read: leave it empty or 0"));
            }
        }
        let (rtp, rfp, sdis) = (get(0).unwrap_or(0.0), get(1).unwrap_or(0.0), get(2).unwrap_or(0.0).abs());
        let (depth, relative) = match (get(3), get(4)) {
            (_, Some(dpr)) if dpr != 0.0 => (rfp - dpr.abs(), true),
            (Some(dp), _) => (dp, false),
            _ => return Err(format!("{name} without its final depth DP or DPR")),
        };
        let dwell_at = |k: usize, what: &str| match get(k).unwrap_or(0.0) {
            d if d < 0.0 => Err(format!("{name}: the dwell {what} in revolutions ({d}) is not read: give it in seconds")),
            d => Ok(d),
        };
        let (dwell, pecking) = match number {
            81 => (0.0, None),
            82 => (dwell_at(5, "DTB")?, None),
            _ => {
                let p = Self::pecking(v, rfp, inch)?;
                let last = dwell_at(15, "_DTD")?;
                (if last > 0.0 { last } else { p.dwell_each }, Some(p))
            }
        };
        let start = rfp + sdis;
        if depth >= start {
            return Err(format!("{name}: the final depth {depth} is not below the reference plane plus the safety distance {start}"));
        }
        if rtp < start {
            return Err(format!("{name}: the retraction plane RTP {rtp} is below the reference plane plus the safety distance {start}"));
        }
        Ok(Drilling { number, rtp, rfp, sdis, depth, relative, dwell, pecking, call })
    }

    /// CYCLE83's infeeds and retractions (the parameters after DPR).
    fn pecking(v: &[Option<f64>], rfp: f64, inch: bool) -> Result<Pecking, String> {
        let get = |k: usize| v.get(k).copied().flatten();
        let (infeed, relative) = match (get(FDEP), get(FDEP + 1)) {
            (_, Some(fdpr)) if fdpr != 0.0 => (fdpr.abs(), true),
            (Some(fdep), _) => (rfp - fdep, false),
            _ => return Err("CYCLE83 without its first drilling depth FDEP or FDPR".into()),
        };
        if infeed <= 0.0 {
            return Err(format!("CYCLE83: the first drilling depth FDEP {} is not below the reference plane {rfp}", rfp - infeed));
        }
        if let Some(dam) = get(FDEP + 2).filter(|&d| d != 0.0) {
            return Err(format!(
                "CYCLE83: the degression DAM {dam} is not read (its rule for the last infeeds is not confirmed): leave DAM 0 for infeeds of the first depth"
            ));
        }
        if let Some(axis) = get(VARI + 1).filter(|&a| a != 0.0 && a != 3.0) {
            return Err(format!("CYCLE83: the tool axis _AXN {axis} is not read: drilling along Z (_AXN 3 or empty) in G17"));
        }
        let vari = get(VARI).unwrap_or(0.0);
        if vari != 0.0 && vari != 1.0 {
            return Err(format!("CYCLE83: VARI {vari} is neither 0 (chip breaking) nor 1 (swarf removal)"));
        }
        let swarf = vari == 1.0;
        let back = if swarf {
            get(DIS1).filter(|&d| d > 0.0).ok_or(
                "CYCLE83: swarf removal (VARI 1) with the anticipation distance computed by the cycle (_DIS1 empty or 0) is not read: give _DIS1",
            )?
        } else {
            match get(VRT).unwrap_or(0.0) {
                d if d < 0.0 => return Err(format!("CYCLE83: the retraction _VRT {d} is negative")),
                d if d > 0.0 => d,
                _ => 1.0 / if inch { MM_PER_INCH } else { 1.0 },
            }
        };
        let dwell = |k: usize, what: &str| match get(k).unwrap_or(0.0) {
            d if d < 0.0 => Err(format!("CYCLE83: the dwell {what} in revolutions ({d}) is not read: give it in seconds")),
            d => Ok(d),
        };
        Ok(Pecking { infeed, relative, swarf, back, dwell_each: dwell(FDEP + 3, "DTB")?, dwell_start: dwell(FDEP + 4, "DTS")? })
    }

    /// RFP + SDIS: where the feed starts.
    pub fn start(&self) -> f64 {
        self.rfp + self.sdis
    }

    /// The number of infeeds before the last one (to the final depth).
    pub fn pecks(&self) -> u32 {
        self.pecking.map_or(0, |p| pecks(self.rfp, self.depth, p.infeed))
    }

    /// The cycle's moves and dwells after the positioning in the plane.
    pub fn strokes(&self) -> Vec<Stroke> {
        let start = self.start();
        let mut out = vec![Stroke::Rapid(start)];
        if let Some(p) = self.pecking {
            for k in 1..=self.pecks() {
                let d = self.rfp - f64::from(k) * p.infeed;
                out.push(Stroke::Feed(d));
                if p.dwell_each > 0.0 {
                    out.push(Stroke::Dwell(p.dwell_each));
                }
                if p.swarf {
                    out.push(Stroke::Rapid(start));
                    if p.dwell_start > 0.0 {
                        out.push(Stroke::Dwell(p.dwell_start));
                    }
                    out.push(Stroke::Rapid((d + p.back).min(start)));
                } else {
                    out.push(Stroke::Feed(d + p.back));
                }
            }
        }
        out.push(Stroke::Feed(self.depth));
        if self.dwell > 0.0 {
            out.push(Stroke::Dwell(self.dwell));
        }
        out.push(Stroke::Rapid(self.rtp));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn of(number: u16, v: &[Option<f64>]) -> Result<Drilling, String> {
        Drilling::of(number, v, false, String::new())
    }

    #[test]
    fn depth_from_dp_or_dpr_and_the_mode_parameters() {
        let d = of(81, &[Some(15.0), Some(0.0), Some(2.0), Some(-12.0), None]).unwrap();
        assert_eq!((d.rtp, d.start(), d.depth, d.dwell), (15.0, 2.0, -12.0, 0.0));
        // DPR (without sign) counts over DP
        let d = of(82, &[Some(15.0), Some(1.0), Some(2.0), Some(-30.0), Some(-8.0), Some(0.5)]).unwrap();
        assert_eq!((d.start(), d.depth, d.dwell, d.relative), (3.0, -7.0, 0.5, true));
        let sl = [Some(10.0), Some(0.0), Some(2.0), Some(-4.0), None, Some(0.0), Some(1.0), None];
        assert_eq!(of(81, &sl).unwrap().depth, -4.0);
        let mut amode = sl;
        amode[7] = Some(10.0);
        assert!(of(81, &amode).unwrap_err().contains("_AMODE 10"));
        assert!(of(81, &[Some(10.0), Some(0.0), Some(2.0)]).unwrap_err().contains("without its final depth"));
        assert!(of(81, &[Some(1.0), Some(0.0), Some(2.0), Some(-4.0)]).unwrap_err().contains("RTP 1 is below"));
        assert!(of(82, &[Some(10.0), Some(0.0), Some(2.0), Some(-4.0), None, Some(-2.0)]).unwrap_err().contains("revolutions"));
    }

    /// CYCLE83(10, 0, 2, -10, , -4, , 0, , , 1, VARI, , , _VRT, , _DIS1): infeeds of 4 from RFP 0
    /// to -4 and -8, the last to -10.
    #[test]
    fn deep_hole_drilling_strokes() {
        let mut v = vec![Some(10.0), Some(0.0), Some(2.0), Some(-10.0), None, Some(-4.0), None, Some(0.0), None, None, Some(1.0)];
        v.extend([Some(0.0), None, None, Some(0.5), Some(0.0), None]);
        let d = of(83, &v).unwrap();
        use Stroke::*;
        let chip = [Rapid(2.0), Feed(-4.0), Feed(-3.5), Feed(-8.0), Feed(-7.5), Feed(-10.0), Rapid(10.0)];
        assert_eq!(d.strokes(), chip);
        v[11] = Some(1.0);
        assert!(of(83, &v).unwrap_err().contains("give _DIS1"));
        v[16] = Some(0.6);
        v[9] = Some(0.2);
        let swarf = [Rapid(2.0), Feed(-4.0), Rapid(2.0), Dwell(0.2), Rapid(-3.4), Feed(-8.0), Rapid(2.0), Dwell(0.2), Rapid(-7.4)];
        assert_eq!(&of(83, &v).unwrap().strokes()[..9], swarf);
        v[7] = Some(1.0);
        assert!(of(83, &v).unwrap_err().contains("degression DAM 1"));
        // _VRT 0 is 1 mm, in an inch program 1/25.4 inch
        v[7] = None;
        v[11] = None;
        v[14] = None;
        let inch = Drilling::of(83, &v, true, String::new()).unwrap();
        assert!((inch.pecking.unwrap().back - 1.0 / 25.4).abs() < 1e-15);
    }
}
