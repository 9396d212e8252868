//! Arcs by their opening angle `AR=` (SINUMERIK 840D sl Programming Manual Fundamentals,
//! "Circular interpolation with opening angle and center point (AR, I, J, K)" and "... opening
//! angle and end point (AR, X, Y, Z)"): `G2`/`G3` with the end point and `AR=`, or with the
//! centre `I J K` (incremental from the start, or `=AC(..)`) and `AR=`, the angle in degrees, the
//! direction that of G2 (clockwise seen from the plane's normal) or G3.
//!
//! With the end point E and the start S (chord c = |E - S|, middle M), an arc of opening angle
//! a has the radius r = c / (2 sin(a/2)) and its centre on the chord's perpendicular bisector at
//! d = c / (2 tan(a/2)) from M: on the left of S -> E for G3, on the right for G2 (d < 0 past 180
//! degrees puts it on the other side). With the centre C, the end is S turned about C by a (G3)
//! or -a (G2). Coordinates are those of the plane's first and second axes, program units.

/// The letter the reader gives the `AR=` word (a letter no block address uses).
pub const AR: u8 = b'&';

/// The centre of the arc from `start` to `end` with the opening angle `degrees` (0 < a < 360).
pub fn centre_from_end(clockwise: bool, start: [f64; 2], end: [f64; 2], degrees: f64) -> Result<[f64; 2], String> {
    if !(degrees > 0.0 && degrees < 360.0) {
        return Err(format!("AR={degrees}: the opening angle of an arc to an end point is more than 0 and less than 360 degrees"));
    }
    let (dx, dy) = (end[0] - start[0], end[1] - start[1]);
    let c = dx.hypot(dy);
    if c == 0.0 {
        return Err("AR= with an end point where the arc starts: give the centre (I J K) for a full circle".into());
    }
    let d = c / (2.0 * (degrees.to_radians() / 2.0).tan());
    // the unit normal on the left of the chord (turned +90 degrees), towards the centre for G3
    let side = if clockwise { -1.0 } else { 1.0 };
    let (nx, ny) = (-dy / c, dx / c);
    Ok([(start[0] + end[0]) / 2.0 + side * d * nx, (start[1] + end[1]) / 2.0 + side * d * ny])
}

/// The end of the arc from `start` about `centre` through the opening angle `degrees`
/// (0 < a <= 360: 360 is the full circle).
pub fn end_from_centre(clockwise: bool, start: [f64; 2], centre: [f64; 2], degrees: f64) -> Result<[f64; 2], String> {
    if !(degrees > 0.0 && degrees <= 360.0) {
        return Err(format!("AR={degrees}: the opening angle of an arc about a centre is more than 0 and at most 360 degrees"));
    }
    if degrees == 360.0 {
        return Ok(start);
    }
    let t = if clockwise { -degrees } else { degrees }.to_radians();
    let (u, v) = (start[0] - centre[0], start[1] - centre[1]);
    let (s, c) = t.sin_cos();
    Ok([centre[0] + u * c - v * s, centre[1] + u * s + v * c])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn near(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    #[test]
    fn quarter_half_and_three_quarter_arcs() {
        // G3 from (10,0) to (0,10), 90 degrees: centre at the origin (left of the chord)
        assert!(near(centre_from_end(false, [10.0, 0.0], [0.0, 10.0], 90.0).unwrap(), [0.0, 0.0]));
        // the same chord with G2: the centre mirrored over the chord
        assert!(near(centre_from_end(true, [10.0, 0.0], [0.0, 10.0], 90.0).unwrap(), [10.0, 10.0]));
        // G3 270 degrees: the centre on the right of the chord, (10,10)
        assert!(near(centre_from_end(false, [10.0, 0.0], [0.0, 10.0], 270.0).unwrap(), [10.0, 10.0]));
        // a half circle: the centre at the chord's middle
        assert!(near(centre_from_end(true, [0.0, 0.0], [20.0, 0.0], 180.0).unwrap(), [10.0, 0.0]));
        // the end from the centre: G3 90 from (10,0) about the origin is (0,10), G2 is (0,-10)
        assert!(near(end_from_centre(false, [10.0, 0.0], [0.0, 0.0], 90.0).unwrap(), [0.0, 10.0]));
        assert!(near(end_from_centre(true, [10.0, 0.0], [0.0, 0.0], 90.0).unwrap(), [0.0, -10.0]));
        assert_eq!(end_from_centre(true, [10.0, 0.0], [0.0, 0.0], 360.0).unwrap(), [10.0, 0.0]);
        assert!(centre_from_end(false, [0.0, 0.0], [1.0, 0.0], 360.0).unwrap_err().contains("less than 360"));
        assert!(centre_from_end(false, [1.0, 0.0], [1.0, 0.0], 90.0).unwrap_err().contains("full circle"));
        assert!(end_from_centre(false, [1.0, 0.0], [0.0, 0.0], -5.0).is_err());
    }
}
