//! The SINUMERIK rewriting's tests: a few blocks in, their RS274/NGC out, run by rs274, the
//! positions it reaches against the values worked out here from the 840D manual.

use super::super::rs274::{rs274, Canon, Kind};
use super::siemens_to_ngc;

/// rs274's moves of the rewriting of `text` (tool 1 one inch long), or `None` without rs274.
fn run(text: &str) -> Option<(String, Vec<Canon>)> {
    let rs = rs274()?;
    let ngc = siemens_to_ngc(text, &[]).unwrap_or_else(|| panic!("not rewritten: {text}"));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("p.ngc"), &ngc).unwrap();
    std::fs::write(dir.path().join("t.tbl"), "T1 P1 Z1\n").unwrap();
    let moves = rs.run(dir.path(), "p.ngc", Some("t.tbl")).unwrap_or_else(|e| panic!("{e}\n{ngc}"));
    Some((ngc, moves))
}

/// The moves' ends (machine X Y Z, mm) are `ends` within 1e-9 mm.
fn ends(moves: &[Canon], ends: &[[f64; 3]], ngc: &str) {
    let seen: Vec<[f64; 3]> = moves.iter().map(|m| [m.end[0], m.end[1], m.end[2]]).collect();
    assert_eq!(seen.len(), ends.len(), "{seen:?}\n{ngc}");
    for (i, (a, b)) in seen.iter().zip(ends).enumerate() {
        assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9), "move {}: {a:?}, not {b:?}\n{ngc}", i + 1);
    }
}

/// R parameters and the functions in degrees: R4 = 40/2 + sqrt(9 + 16) - 6 = 19,
/// TRUNC(-2.5) = -2 (towards zero), ROUND(-2.5) = -3, ATAN2(1, -1) = 135, SIN(30) * 4 = 2,
/// COS(60) + ABS(-1) + EXP(0) + LN(1) + TAN(45) + ASIN(1)/90 + ACOS(0)/90 = 5.5.
#[test]
fn parameters_and_functions_in_degrees() {
    let text = "N10 G17 G71 G90\nN20 R1=40 R2=-2.5\nN30 R4=R1/2+SQRT(POT(3)+POT(4))-2*3 ; 19\n\
                N40 G0 X=R4 Y=TRUNC(R2) Z=ROUND(R2)\nN50 G1 X=ATAN2(1,-1) Y=-R2*2 Z=SIN(30)*4 F100\n\
                N60 X=COS(60)+ABS(-1)+EXP(0)+LN(1)+TAN(45)+ASIN(1)/90+ACOS(0)/90\nN70 M30\n";
    let Some((ngc, moves)) = run(text) else { return };
    ends(&moves, &[[19.0, -2.0, -3.0], [135.0, 5.0, 2.0], [5.5, 5.0, 2.0]], &ngc);
    assert!(ngc.contains("#1004=[#1001/2+SQRT[[[3]*[3]]+[[4]*[4]]]-2*3]\n"), "{ngc}");
}

/// `CR=10` from (0, 0) to (10, 10) in G3 turns round (0, 10), on the left of the chord;
/// `CR=-10` from (10, 10) to (0, 20) round (10, 20), on its right (over 180 degrees);
/// `X=IC(5) Y=AC(3)` from (0, 20) is (5, 3); `G2 X15 Y3 I=AC(10) J=IC(0)` turns round
/// (10, 3); in G91 `X=AC(20) Y=IC(1)` is (20, 4).
#[test]
fn arcs_by_radius_absolute_centres_and_values_in_the_other_mode() {
    let text = "N10 G17 G71 G90 G0 X0 Y0 Z0\nN20 G3 X10 Y10 CR=10 F100\nN30 G3 X0 Y20 CR=-10\n\
                N40 G1 X=IC(5) Y=AC(3)\nN50 G2 X15 Y3 I=AC(10) J=IC(0)\nN60 G91 G1 X=AC(20) Y=IC(1)\nN70 G90 M30\n";
    let Some((ngc, moves)) = run(text) else { return };
    ends(&moves, &[[0.0; 3], [10.0, 10.0, 0.0], [0.0, 20.0, 0.0], [5.0, 3.0, 0.0], [15.0, 3.0, 0.0], [20.0, 4.0, 0.0]], &ngc);
    for (i, centre, turns) in [(1, [0.0, 10.0], 1), (2, [10.0, 20.0], 1), (4, [10.0, 3.0], -1)] {
        let Kind::Arc { centre: c, turns: t, .. } = moves[i].kind else { panic!("an arc: {:?}\n{ngc}", moves[i]) };
        assert!(t == turns && (c[0] - centre[0]).abs() < 1e-9 && (c[1] - centre[1]).abs() < 1e-9, "{:?}\n{ngc}", moves[i]);
    }
    assert!(ngc.contains("G3 X0 Y20 R[[0-10]]\n") && ngc.contains("G90.1 G2 X15 Y3 I[10] J[#5421+[0]]\nG91.1\n"), "{ngc}");
}

/// The frame, the tool, the cycles: `TRANS X10 Y5` then `ATRANS X1` puts the zero at (11, 5);
/// T1 (25.4 mm) with M6; under `MCALL CYCLE82(30, 0, 2, , 5, 1)` from Z 30 (its RTP) each
/// position is LinuxCNC's G98 G82: the move there, G0 to 2, G1 to -5 (DPR 5 under RFP 0), G0
/// to 30; a direct `CYCLE81(40, 0, 1, -3)` is G0 to 1, G1 to -3, G0 to 40; under `MCALL
/// CYCLE81(20, 0, 1, -3)` from Z 40 the hole runs as the manual's moves (G98 would retract to
/// 40); `SUPA Z0 D0` is machine Z 0 without the tool.
#[test]
fn frames_tools_and_drilling_cycles() {
    let text = "G17 G71 G90\nT1 D1 M6\nTRANS X10 Y5\nG0 X0 Y0 Z30\nATRANS X1\nG0 X0 Y0\nF100\n\
                MCALL CYCLE82(30, 0, 2, , 5, 1)\nX1 Y1\nG0 X2 Y2\nMCALL\nG0 Z50\nCYCLE81(40, 0, 1, -3)\n\
                MCALL CYCLE81(20, 0, 1, -3)\nX5\nMCALL\nTRANS\nG0 SUPA Z0 D0\nM30\n";
    let Some((ngc, moves)) = run(text) else { return };
    let t = 25.4;
    let mut want = vec![[10.0, 5.0, 30.0 + t], [11.0, 5.0, 30.0 + t]];
    for (x, y) in [(12.0, 6.0), (13.0, 7.0)] {
        want.extend([[x, y, 30.0 + t], [x, y, 2.0 + t], [x, y, -5.0 + t], [x, y, 30.0 + t]]);
    }
    want.extend([[13.0, 7.0, 50.0 + t], [13.0, 7.0, 1.0 + t], [13.0, 7.0, -3.0 + t], [13.0, 7.0, 40.0 + t]]);
    want.extend([[16.0, 7.0, 40.0 + t], [16.0, 7.0, 1.0 + t], [16.0, 7.0, -3.0 + t], [16.0, 7.0, 20.0 + t], [16.0, 7.0, 0.0]]);
    ends(&moves, &want, &ngc);
    assert!(moves.last().unwrap().tool == [0.0; 3] && moves[0].tool == [0.0, 0.0, t], "{ngc}");
    assert!(ngc.contains("G98 G82 X1 Y1 R#2012 Z#2013 P#2014\n") && ngc.contains("T1 M6\nG43 H1\n"), "{ngc}");
}

/// What the rewriting does not take gives `None`, not a wrong program.
#[test]
fn what_is_not_rewritten_gives_none() {
    for block in [
        "G2 X10 Y0 AR=90",
        "DEF REAL DEPTH",
        "GOTOF END",
        "CYCLE83(10, 0, 1, -20, , -5, , 2, 0, 0, 1, 0)",
        "G41 X0 Y0",
        "T1 D2 M6",
        "T=\"MILL6\"",
        "R1=2 X=R1",
        "T1 D1 M6\nG0 SUPA Z0",
        "G18 CYCLE81(10, 0, 1, -5)",
        "MCALL CYCLE81(10, 0, 1, -5)\nZ5",
        "PROC PART(REAL X1)",
        "L20",
        "/G0 X5",
        "ROT RPL=30",
    ] {
        let text = format!("G17 G71 G90\n{block}\nM30\n");
        assert_eq!(siemens_to_ngc(&text, &[]), None, "{block}");
    }
}
