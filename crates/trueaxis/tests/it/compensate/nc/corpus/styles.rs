//! The styles of the corpus: for each CAM post-processor (or hand-writing habit) and controller,
//! a program written the way its published output is written (docs/nc.md lists the published
//! programs studied and what each style takes from them), varied by the part (`Part::new(k, ..)`):
//! header comments, safety blocks, tool changes, work offsets, number formats, arcs, cycles, ends.
//! No published file is copied; the geometry is this module's own.

use super::writer::{ArcWords, Cycle, Digits, Part, W};
use trueaxis::compensate::nc::Controller;

/// One program of the corpus.
pub struct Sample {
    pub post: &'static str,
    pub controller: &'static str,
    /// The dialect its user names (`--dialect`).
    pub dialect: Controller,
    pub name: String,
    pub bytes: Vec<u8>,
    /// Written for a LinuxCNC-compatible controller (LinuxCNC, PathPilot, Mach3, grbl): checked
    /// through LinuxCNC's rs274; otherwise by a second reading of the Fanuc-dialect program.
    pub rs274: bool,
}

/// A style: post, controller, its dialect, whether rs274 reads it, the program of variant k.
pub type Style = (&'static str, &'static str, Controller, bool, fn(usize) -> Vec<u8>);

pub const STYLES: [Style; 26] = [
    ("Fusion 360 haas.cps", "Haas NGC", Controller::Haas, false, fusion_haas),
    ("Fusion 360 fanuc.cps", "Fanuc 0i", Controller::Fanuc, false, fusion_fanuc),
    ("Mastercam MPFAN", "Fanuc 0i", Controller::Fanuc, false, mastercam),
    ("CAMWorks Fanuc post", "Fanuc 0i", Controller::Fanuc, false, camworks),
    ("hand-written Haas macro", "Haas NGC", Controller::Haas, false, haas_macro),
    ("hand-written Fanuc Custom Macro B", "Fanuc 30i", Controller::Fanuc, false, fanuc_macro),
    ("Fadal format 2 (hand-written)", "Fadal 88HS", Controller::Fadal, false, fadal),
    ("Fusion 360 mach3mill.cps", "Mach3", Controller::Mach3, true, fusion_mach3),
    ("CamBam Mach3 post", "Mach3", Controller::Mach3, true, cambam),
    ("SketchUcam", "Mach3", Controller::Mach3, true, sketchucam),
    ("Fusion 360 grbl.cps (OpenBuilds)", "grbl 1.1", Controller::Grbl, true, fusion_grbl),
    ("pcb2gcode --nog64 --nom6", "grbl 1.1", Controller::Grbl, true, pcb2gcode_grbl),
    ("pcb2gcode", "LinuxCNC 2.9", Controller::LinuxCnc, true, pcb2gcode),
    ("Fusion 360 linuxcnc.cps", "LinuxCNC 2.9", Controller::LinuxCnc, true, fusion_linuxcnc),
    ("Fusion 360 tormach.cps", "Tormach PathPilot", Controller::LinuxCnc, true, tormach),
    ("PyCAM", "LinuxCNC 2.9", Controller::LinuxCnc, true, pycam),
    ("HeeksCNC emc2b", "LinuxCNC 2.9", Controller::LinuxCnc, true, heekscnc),
    ("hand-written LinuxCNC (O-words)", "LinuxCNC 2.9", Controller::LinuxCnc, true, linuxcnc_hand),
    ("Fusion 360 mach3mill.cps (subroutines)", "Mach3", Controller::Mach3, true, fusion_mach3_subs),
    ("hand-written Haas (M97 local subprograms)", "Haas NGC", Controller::Haas, false, haas_m97),
    ("grbl sender stream ($H, $X, $J=)", "grbl 1.1", Controller::Grbl, true, grbl_stream),
    ("Fusion 360 siemens-840d.cps", "SINUMERIK 840D sl", Controller::Siemens, false, fusion_siemens),
    ("hand-written 840D (R parameters, frames)", "SINUMERIK 840D sl", Controller::Siemens, false, siemens_hand),
    ("hand-written 840D (loops, DEF, jumps, AR= arcs)", "SINUMERIK 840D sl", Controller::Siemens, false, siemens_flow),
    ("Fusion 360 fadal.cps (E fixture offsets)", "Fadal 88HS", Controller::Fadal, false, fusion_fadal),
    ("hand-written Fadal macro (# V loop, M98)", "Fadal 88HS", Controller::Fadal, false, fadal_macro),
];

/// The whole corpus: `per_style` variants of each style.
pub fn corpus(per_style: usize) -> Vec<Sample> {
    let mut out = Vec::new();
    for (post, controller, dialect, rs274, f) in STYLES {
        for k in 0..per_style {
            let slug: String = post.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '_' }).collect();
            let ext = if rs274 { "ngc" } else { "nc" };
            out.push(Sample { post, controller, dialect, name: format!("{slug}_{k}.{ext}"), bytes: f(k), rs274 });
        }
    }
    out
}

/// CR LF line ends (Windows posts).
fn crlf(s: String) -> Vec<u8> {
    s.replace('\n', "\r\n").into_bytes()
}

/// Latin-1 bytes for the characters below U+0100 (European comments), others as UTF-8.
fn latin1(s: &str) -> Vec<u8> {
    let mut out = Vec::new();
    for c in s.chars() {
        if (c as u32) < 256 {
            out.push(c as u32 as u8);
        } else {
            out.extend(c.to_string().bytes());
        }
    }
    out
}

fn units(p: &Part) -> &'static str {
    if p.inch {
        "G20"
    } else {
        "G21"
    }
}

/// Fusion 360 for Haas (NGC): `%`, `O0nnnn`, a tool list, the safety block, `G28 G91 Z0.`, `G154 P`
/// or `G54`, `G43 Z.. H..`, `G187` smoothing, `M29`-less rigid tapping (`G84`), `G103 P1` around
/// cycles, `G28 G91 X0. Y0.` at the end.
fn fusion_haas(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 3 == 2);
    let mut w = W::new(Digits::Trim(if p.inch { 4 } else { 3 }, true), " ");
    w.raw("%");
    w.raw(&format!("O{:05} (PART {k})", 1000 + k));
    w.raw(&format!("(T1 D=6. CR=0. - ZMIN=-{} - FLAT END MILL)", w.num(p.depth)));
    w.raw("(T2 D=5. CR=0. TAPER=118DEG - ZMIN=-8. - DRILL)");
    w.line("G90 G94 G17 G49 G40 G80");
    w.line(units(&p));
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.raw("(CONTOUR2D)");
    w.line("T1 M6");
    w.line(&format!("S{} M3", p.spindle));
    w.line(if k % 2 == 0 { "G154 P1" } else { "G54" });
    w.line("M8");
    if k % 4 == 1 {
        w.line("G187 P2 E0.05");
    }
    let xm = p.x0 + p.w / 2.0;
    w.rapid(Some(xm), Some(p.y0), None);
    w.line(&format!("G43 Z{} H1", w.num(p.clear)));
    w.reset();
    w.contour(&p);
    w.line("G187");
    w.line("M9");
    w.line("M5");
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.reset();
    w.raw("(DRILL)");
    w.line("T2 M6");
    w.line(&format!("S{} M3", p.spindle / 2));
    w.line("G54");
    w.line("G103 P1");
    w.rapid(Some(p.holes[0][0]), Some(p.holes[0][1]), None);
    w.line(&format!("G43 Z{} H2", w.num(p.clear)));
    w.reset();
    w.cycle(&p, "G98", p.cycle);
    w.line("G103");
    w.line("M5");
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.line("G28 G91 X0. Y0.");
    w.line("G90");
    w.line("M30");
    w.raw("%");
    w.out.into_bytes()
}

/// Fusion 360 for Fanuc: sequence numbers by 5, the same safety block, `G43 Z.. H..`, G83 with Q,
/// tool radius compensation in control (`G41 D1`) in one variant of ten (refused by design).
fn fusion_fanuc(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 4 == 3);
    let mut w = W::new(Digits::Trim(if p.inch { 4 } else { 3 }, true), " ");
    w.raw("%");
    w.raw(&format!("O{} (FANUC {k})", 2000 + k));
    w.raw("(T1  D=8. CR=0. - ZMIN=-3. - FLAT END MILL)");
    w.seq = Some((10, 5));
    w.line("G90 G94 G17 G49 G40 G80");
    w.line(units(&p));
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.raw("(FACE1)");
    w.line("T1 M06");
    w.line(&format!("S{} M03", p.spindle));
    w.line("G54");
    w.line("M08");
    w.rapid(Some(p.x0), Some(p.y0), None);
    w.line(&format!("G43 Z{} H01", w.num(p.clear)));
    w.reset();
    w.facing(&p);
    if k == 9 {
        w.line("G41 D01");
    }
    w.contour(&p);
    if k == 9 {
        w.line("G40");
    }
    w.line("M09");
    w.line("M05");
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.reset();
    w.raw("(DRILL1)");
    w.line("T2 M06");
    w.line(&format!("S{} M03", p.spindle / 2));
    w.line("G54");
    w.rapid(Some(p.holes[0][0]), Some(p.holes[0][1]), None);
    w.line(&format!("G43 Z{} H02", w.num(p.clear)));
    w.reset();
    w.cycle(&p, "G98", if p.cycle == Cycle::Bore { Cycle::Peck } else { p.cycle });
    w.line("M05");
    w.line("G28 G91 Z0.");
    w.line("G28 G91 X0. Y0.");
    w.line("G90");
    w.line("M30");
    w.raw("%");
    w.out.into_bytes()
}

/// Mastercam's generic Fanuc post (MPFAN): `O0000(NAME)`, the DATE/TIME/MCX/NC FILE/MATERIAL
/// comments, the tool table comment, `G0 G17 G40 G49 G80 G90`, `G0 G90 G54 X.. Y.. S.. M3` with
/// the spindle on the first move, `G43 H1 Z..`, `G99` cycles, `G91 G28 Z0.`, `G28 X0. Y0.`, CR LF.
fn mastercam(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 2 == 1);
    let mut w = W::new(Digits::Trim(4, true), " ");
    w.raw("%");
    w.raw(&format!("O{:04}(MC PART {k})", 3000 + k));
    w.raw("(DATE=DD-MM-YY - 27-11-26 TIME=HH:MM - 10:15)");
    w.raw(&format!("(MCX FILE - C:\\USERS\\SHOP\\PART{k}.MCAM)"));
    w.raw(&format!("(MATERIAL - ALUMINUM {} - 6061)", if p.inch { "INCH" } else { "MM" }));
    w.raw("( T1 |  1/4 FLAT ENDMILL | H1 )");
    w.seq = Some((100, 2));
    w.line(units(&p));
    w.line("G0 G17 G40 G49 G80 G90");
    w.line("T1 M6");
    let xm = p.x0 + p.w / 2.0;
    w.line(&format!("G0 G90 G54 X{} Y{} S{} M3", w.num(xm), w.num(p.y0), p.spindle));
    w.line(&format!("G43 H1 Z{}", w.num(p.clear)));
    w.reset();
    w.rapid(Some(xm), Some(p.y0), Some(p.clear));
    w.contour(&p);
    w.line("M5");
    w.line("G91 G28 Z0.");
    w.line("M01");
    w.reset();
    w.line("T2 M6");
    w.line(&format!("G0 G90 G54 X{} Y{} S{} M3", w.num(p.holes[0][0]), w.num(p.holes[0][1]), p.spindle / 2));
    w.line(&format!("G43 H2 Z{}", w.num(p.clear)));
    w.reset();
    w.cycle(&p, "G99", p.cycle);
    w.line("M5");
    w.line("G91 G28 Z0.");
    w.line("G28 X0. Y0.");
    w.line("M30");
    w.raw("%");
    crlf(w.out)
}

/// A CAMWorks Fanuc post: `O` number, `N1`-step sequence numbers on every block, modal codes
/// each on the safety line, `G90 G00 G54 X.. Y..`, `G43 H.. Z..`, tool numbers as `T01`, two
/// decimals less common: four in inch, three in mm.
fn camworks(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 2 == 0);
    let mut w = W::new(Digits::Trim(if p.inch { 4 } else { 3 }, true), " ");
    w.raw("%");
    w.raw(&format!("O{:04}", 4000 + k));
    w.raw(&format!("(CAMWORKS PART {k} - MILL2AX)"));
    w.seq = Some((1, 1));
    w.line(&format!("{} G17 G40 G49 G80 G90", units(&p)));
    w.line("T01 M06");
    w.line(&format!("S{} M03", p.spindle));
    w.line(&format!("G90 G00 G54 X{} Y{}", w.num(p.x0), w.num(p.y0)));
    w.line(&format!("G43 H01 Z{} M08", w.num(p.clear)));
    w.reset();
    w.rapid(Some(p.x0), Some(p.y0), Some(p.clear));
    w.modal_g = false;
    w.facing(&p);
    w.contour(&p);
    w.line("M09");
    w.line("G91 G28 Z0. M05");
    w.line("G90");
    w.reset();
    w.line("T02 M06");
    w.line(&format!("S{} M03", p.spindle / 2));
    w.line(&format!("G90 G00 G54 X{} Y{}", w.num(p.holes[0][0]), w.num(p.holes[0][1])));
    w.line(&format!("G43 H02 Z{}", w.num(p.clear)));
    w.reset();
    w.cycle(&p, "G98", p.cycle);
    w.line("G91 G28 Z0. M05");
    w.line("G90");
    w.line("M30");
    w.raw("%");
    w.out.into_bytes()
}

/// A Haas program written at the machine: `:` or `O` program number, `G154 P`, a bolt circle in a
/// `WHILE` loop of macro variables, a part counter `#3901`, `DPRNT` output between `POPEN`/`PCLOS`.
fn haas_macro(k: usize) -> Vec<u8> {
    let n = 4 + k % 5;
    let r = 20.0 + 3.0 * k as f64;
    let number = if k % 2 == 0 { format!(":{}", 5000 + k) } else { format!("O{:05}", 5000 + k) };
    let offset = if k % 3 == 0 { "G54".to_string() } else { format!("G154 P{}", 1 + k % 20) };
    format!(
        "%\n{number} (BOLT CIRCLE {n} HOLES)\nG00 G17 G40 G49 G80 G90\nG21\n{offset}\nT3 M06 (DRILL 6.8)\nS1800 M03\n\
         G00 X0. Y0.\nG43 H03 Z25. M08\n#100 = {n} (HOLES)\n#101 = {r:.1} (RADIUS)\n#102 = 0 (COUNT)\n#103 = {} (START ANGLE)\n\
         WHILE [#102 LT #100] DO1\n#104 = #103 + #102 * 360. / #100\nX[#101 * COS[#104]] Y[#101 * SIN[#104]]\n\
         G98 G81 Z-{}. R2. F120.\nG80\n#102 = #102 + 1\nEND1\nG00 Z25. M09\n#3901 = #3901 + 1\nPOPEN\nDPRNT[PART*#3901[40]*DONE]\nPCLOS\n\
         M05\nG28 G91 Z0.\nG90\nM30\n%\n",
        15 * (k % 3),
        8 + k % 4
    )
    .into_bytes()
}

/// A Fanuc Custom Macro B program: a `G65` call of a slot macro with arguments, an `IF [...] GOTO`
/// loop, an `M98 P.. L..` subprogram of incremental moves, `#500` common variables, `;` ends of
/// block (as a Fanuc punches them).
fn fanuc_macro(k: usize) -> Vec<u8> {
    let l = 20.0 + 2.0 * k as f64;
    let repeat = 2 + k % 3;
    let eob = if k % 2 == 0 { ";" } else { "" };
    let lines = [
        "%".to_string(),
        format!("O{} (SLOTS)", 6000 + k),
        "G21 G17 G40 G49 G80 G90".into(),
        "T4 M06".into(),
        "S3000 M03".into(),
        "G00 G54 X0. Y0.".into(),
        "G43 H04 Z20.".into(),
        format!("#500 = {l:.1}"),
        "#1 = 0".into(),
        "N10 IF [#1 GE 3] GOTO 20".into(),
        "G65 P9010 X[#1 * 15.] Y-10. I#500 D2.".into(),
        "#1 = #1 + 1".into(),
        "GOTO 10".into(),
        "N20 G00 X-30. Y20.".into(),
        format!("M98 P1100 L{repeat}"),
        "G90 G00 Z20.".into(),
        "G91 G28 Z0.".into(),
        "M30".into(),
        "O9010 (SLOT: X Y START, I LENGTH, D DEPTH)".into(),
        "G90 G00 X#24 Y#25".into(),
        "Z2.".into(),
        "G01 Z-#7 F150.".into(),
        "G91 Y#4 F400.".into(),
        "G90 G00 Z20.".into(),
        "M99".into(),
        "O1100 (STEP)".into(),
        "G91 G01 Z-22. F150.".into(),
        "X12. F400.".into(),
        "G00 Z22.".into(),
        "X3.".into(),
        "M99".into(),
        "%".into(),
    ];
    let mut s = String::new();
    for line in lines {
        let end = if line == "%" || line.starts_with('O') { "" } else { eob };
        s.push_str(&line);
        s.push_str(end);
        s.push('\n');
    }
    s.into_bytes()
}

/// Fadal in format 2 (Fanuc-like), as Fadal programmers write it: `N1 O.. (NAME)` on the first
/// line, `G0 G90 G80 G40 G17`, fixture offset `G54`, `M6 T1`, `G43 H1 Z..`, a `G81` with `G98`, an
/// `M98` subprogram.
fn fadal(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 2 == 0);
    let mut w = W::new(Digits::Trim(4, true), " ");
    w.raw("%");
    w.seq = Some((1, 1));
    w.line(&format!("O{} (FADAL {k})", 7000 + k));
    w.line(&format!("G0 G90 G80 G40 G17 {}", units(&p)));
    w.line("M6 T1");
    w.line(&format!("G54 X{} Y{} S{} M3", w.num(p.x0), w.num(p.y0), p.spindle));
    w.line(&format!("G43 H1 Z{} M8", w.num(p.clear)));
    w.reset();
    w.rapid(Some(p.x0), Some(p.y0), Some(p.clear));
    w.facing(&p);
    w.contour(&p);
    w.line("G0 G91 G28 Z0. M5");
    w.line("G90");
    w.reset();
    w.line("M6 T2");
    w.line(&format!("G54 X{} Y{} S{} M3", w.num(p.holes[0][0]), w.num(p.holes[0][1]), p.spindle / 2));
    w.line(&format!("G43 H2 Z{}", w.num(p.clear)));
    w.reset();
    w.cycle(&p, "G98", Cycle::Drill);
    w.line("G0 G91 G28 Z0. M5");
    w.line("G90");
    w.line("M30");
    w.raw("%");
    w.out.into_bytes()
}

/// Fusion 360 for Mach3: `%`, the program name as a comment, `G90 G94 G91.1 G40 G49 G17`,
/// `G28 G91 Z0.`, `T1 M6`, `G43 Z.. H1`, G83 cycles.
fn fusion_mach3(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 3 == 1);
    let mut w = W::new(Digits::Trim(if p.inch { 4 } else { 3 }, false), " ");
    fusion_mach3_start(&mut w, &p, 1000 + k);
    w.rapid(Some(p.x0 + p.w / 2.0), Some(p.y0), None);
    w.line(&format!("G43 Z{} H1", w.num(p.clear)));
    w.reset();
    w.contour(&p);
    w.line("M5");
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.reset();
    w.line("T2 M6");
    w.line(&format!("S{} M3", p.spindle / 2));
    w.rapid(Some(p.holes[0][0]), Some(p.holes[0][1]), None);
    w.line(&format!("G43 Z{} H2", w.num(p.clear)));
    w.reset();
    w.cycle(&p, "G98", if p.cycle == Cycle::Tap { Cycle::Drill } else { p.cycle });
    w.line("M5");
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.line("M30");
    w.raw("%");
    w.out.into_bytes()
}

/// The start of a Fusion 360 program for Mach3: `%`, the program name as a comment, the tool, the
/// safety block, the reference return, the first tool change, `G54`.
fn fusion_mach3_start(w: &mut W, p: &Part, name: usize) {
    w.raw("%");
    w.raw(&format!("({name})"));
    w.raw("(T1 D=6 CR=0 - ZMIN=-3 - FLAT END MILL)");
    w.line("G90 G94 G91.1 G40 G49 G17");
    w.line(units(p));
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.raw("(2D CONTOUR1)");
    w.line("T1 M6");
    w.line(&format!("S{} M3", p.spindle));
    w.line("G54");
}

/// CamBam's default Mach3 post: `( Made using CamBam - ... )`, the drawing name and date, `G21 G90
/// ( G64 ) G40` (G64 commented out), `G0 Z3.0`, `( T1 : 6.0 )`, `G1 F300.0 Z-1.0` (feed before the
/// axes), one-decimal numbers at least, `G81` drilling, CR LF, Latin-1 comments (a European user).
fn cambam(k: usize) -> Vec<u8> {
    let p = Part::new(k, false);
    let mut w = W::new(Digits::Trim(4, true), " ");
    w.feed_first = true;
    w.modal_g = false;
    let num = |v: f64| {
        let s = format!("{v:.4}").trim_end_matches('0').to_string();
        if s.ends_with('.') {
            s + "0"
        } else {
            s
        }
    };
    w.raw("( Made using CamBam - http://www.cambam.co.uk )");
    w.raw(&format!("( Teil{k} 27.11.2026 10:15:00 )"));
    w.raw("( T1 : 6.0 )");
    w.raw("G21 G90 ( G64 ) G40");
    w.raw(&format!("G0 Z{}", num(p.clear)));
    w.raw("( T1 : 6.0 )");
    w.raw("T1 M6");
    w.raw(if k % 2 == 0 { "( Fräse Ø6 - Kontur )" } else { "( Profile1 )" });
    w.raw("G17");
    w.raw(&format!("M3 S{}", p.spindle));
    w.digits = Digits::Trim(4, true);
    w.contour(&p);
    w.raw("( Bohren )");
    w.line(&format!("G0 Z{}", num(p.clear)));
    w.raw(&format!("G81 X{} Y{} Z{} R{} F{}", num(p.holes[0][0]), num(p.holes[0][1]), num(-p.hole_depth), num(p.safe), num(p.plunge)));
    for h in &p.holes[1..] {
        w.raw(&format!("X{} Y{}", num(h[0]), num(h[1])));
    }
    w.raw("G80");
    w.raw(&format!("G0 Z{}", num(p.clear)));
    w.raw("M5");
    w.raw("M30");
    let text = w.out.replace(".\n", ".0\n").replace(". ", ".0 ");
    let bytes = latin1(&text);
    if k % 3 == 0 {
        let mut out = Vec::new();
        for &b in &bytes {
            if b == b'\n' {
                out.push(b'\r');
            }
            out.push(b);
        }
        out
    } else {
        bytes
    }
}

/// SketchUcam (Phlatboyz): `%`, its settings as comments in inch fractions, `G90 G20 G49 G61`,
/// four decimals padded with blanks, lines without a motion code indented, `G17 G3 .. R` arcs with Z.
fn sketchucam(k: usize) -> Vec<u8> {
    let p = Part::new(k, true);
    let mut w = W::new(Digits::Fixed(4), "   ");
    w.arcs = ArcWords::R;
    w.indent = "   ";
    w.raw("%");
    w.raw("(Generated by SketchUcam {1.1b})");
    w.raw("(Bit diameter: 1/8\")");
    w.raw(&format!("(Feed rate: {}\"/min)", p.feed));
    w.raw("(Multipass enabled, Depth = 1/8\")");
    w.raw("G90 G20 G49 G61");
    w.raw(&format!("M3 S{}", p.spindle));
    w.contour(&p);
    w.holes_expanded(&p);
    w.raw("G0 X0 Y0 (home)");
    w.raw("M05");
    w.raw("M30");
    w.raw("%");
    if k % 2 == 0 {
        crlf(w.out)
    } else {
        w.out.into_bytes()
    }
}

/// Fusion 360 for grbl (and the OpenBuilds variant): a header of comments, `G90 G94`, `G17`,
/// `G21`, no tool length offset, tool changes commented out, drilling expanded into moves (grbl has
/// no canned cycles), `M30` without `%`.
fn fusion_grbl(k: usize) -> Vec<u8> {
    let p = Part::new(k, false);
    let mut w = W::new(Digits::Trim(3, false), " ");
    w.raw("(Made in : Autodesk CAM Post Processor)");
    w.raw("(G Code optimized for controller)");
    w.raw(&format!("(Program Name : {})", 1000 + k));
    w.raw("(Units = mm)");
    w.raw("G90 G94");
    w.raw("G17");
    w.raw("G21");
    w.raw("(T1 M6 - Flat End Mill 6mm)");
    w.raw(&format!("S{} M3", p.spindle));
    w.rapid(None, None, Some(p.clear));
    w.facing(&p);
    w.contour(&p);
    w.holes_expanded(&p);
    w.raw("M5");
    w.raw("M30");
    w.out.into_bytes()
}

/// pcb2gcode: comments after every block, `G94`, `G64 P..`, dwell `G04 P1`, `(MSG, ...)` before a
/// tool change `M6` and a pause `M0`, five decimals, only `G1`/`G0` (an outline).
fn pcb2gcode(k: usize) -> Vec<u8> {
    pcb2gcode_flavour(k, false)
}

/// pcb2gcode for grbl (its options `--nog64 --nom6`: grbl knows neither G64 nor M6): the tool
/// change is a message and a pause.
fn pcb2gcode_grbl(k: usize) -> Vec<u8> {
    pcb2gcode_flavour(k, true)
}

fn pcb2gcode_flavour(k: usize, grbl: bool) -> Vec<u8> {
    let p = Part::new(k, k % 2 == 1);
    let mut w = W::new(Digits::Fixed(5), " ");
    w.modal_g = false;
    w.raw(&format!("( pcb2gcode 2.{}.0 )", k % 6));
    w.raw("( Software-independent Gcode )");
    w.raw("G94 ( Millimeters per minute feed rate. )");
    w.raw(&format!("{} ( Units == {}. )", units(&p), if p.inch { "INCHES" } else { "Millimeters" }));
    w.raw("G90 ( Absolute coordinates. )");
    w.raw(&format!("G00 S{} ( RPM spindle speed. )", p.spindle));
    if !grbl {
        w.raw(&format!("G64 P{} ( set maximum deviation from commanded toolpath )", if p.inch { "0.00040" } else { "0.01000" }));
    }
    w.raw(&format!("G01 F{} ( Feedrate. )", w.num(p.feed)));
    w.raw(&format!("G00 Z{} (Retract to tool change height)", w.num(p.clear)));
    w.raw("T2");
    w.raw("M5      (Spindle stop.)");
    w.raw("G04 P1.00000 (Wait for spindle to stop)");
    w.raw("(MSG, Change tool bit to cutter diameter 2.00000mm)");
    if !grbl {
        w.raw("M6      (Tool change.)");
    }
    w.raw("M0      (Temporary machine stop.)");
    w.raw("M3 ( Spindle on clockwise. )");
    w.raw("G04 P1.00000 (Wait for spindle to get up to speed)");
    let (x0, y0, x1, y1) = (p.x0, p.y0, p.x0 + p.w, p.y0 + p.h);
    w.rapid(Some(x0), Some(y0), None);
    for pass in 1..=p.passes {
        let z = -p.depth * pass as f64 / p.passes as f64;
        w.feed(None, None, Some((z * 1e4).round() / 1e4), p.plunge);
        for (x, y) in [(x1, y0), (x1, y1), (x0, y1), (x0, y0)] {
            w.feed(Some(x), Some(y), None, p.feed);
        }
    }
    w.raw(&format!("G00 Z{} ( retract )", w.num(p.clear)));
    w.raw("M5 ( Spindle off. )");
    w.raw("M9 ( Coolant off. )");
    w.raw("M2 ( Program end. )");
    w.out.into_bytes()
}

/// Fusion 360 for LinuxCNC: `%`, `(name)`, `G90 G94 G40 G17 G91.1`, `G53 G0 Z0.` to the top
/// of the travel instead of G28, `T1 M6`, `G43 Z.. H1`, `G98 G83 .. Q` cycles, `G64 P` path mode.
fn fusion_linuxcnc(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 4 == 1);
    let mut w = W::new(Digits::Trim(if p.inch { 4 } else { 3 }, false), " ");
    w.raw("%");
    w.raw(&format!("({})", 1000 + k));
    w.raw("(T1  D=6 CR=0 - ZMIN=-3 - flat end mill)");
    w.line("G90 G94 G40 G17 G91.1");
    w.line(units(&p));
    w.line("G64 P0.01");
    w.raw("(Face1)");
    w.line("T1 M6");
    w.line(&format!("S{} M3", p.spindle));
    w.line("G54");
    w.line("M8");
    w.rapid(Some(p.x0), Some(p.y0), None);
    w.line(&format!("G43 Z{} H1", w.num(p.clear)));
    w.reset();
    w.facing(&p);
    w.contour(&p);
    w.line("M9");
    w.line("M5");
    w.line(&format!("G53 G0 Z{}", if p.inch { "2" } else { "50" }));
    w.reset();
    w.raw("(Drill1)");
    w.line("T2 M6");
    w.line(&format!("S{} M3", p.spindle / 2));
    w.rapid(Some(p.holes[0][0]), Some(p.holes[0][1]), None);
    w.line(&format!("G43 Z{} H2", w.num(p.clear)));
    w.reset();
    w.cycle(&p, "G98", p.cycle);
    w.line("M5");
    w.line(&format!("G53 G0 Z{}", if p.inch { "2" } else { "50" }));
    w.line("M30");
    w.raw("%");
    w.out.into_bytes()
}

/// Fusion 360 for Tormach PathPilot: inch by default, `G90 G94 G40 G17 G80 G49 G64 P..`, `G30`
/// as the tool-change position, `T1 M6 G43 H1` on one line, `G98` cycles, `G30` at the end.
fn tormach(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 3 != 2);
    let mut w = W::new(Digits::Trim(4, true), " ");
    w.raw("%");
    w.raw(&format!("(Tormach {})", 1000 + k));
    w.raw("(T1 D=0.25 CR=0. - ZMIN=-0.1 - flat end mill)");
    w.line(units(&p));
    w.line(&format!("G90 G94 G40 G17 G80 G49 G64 P{}", if p.inch { "0.001" } else { "0.025" }));
    w.line("G30");
    w.raw("(Adaptive1)");
    w.line("T1 M6 G43 H1");
    w.line(&format!("S{} M3", p.spindle));
    w.line(if k % 2 == 0 { "G54" } else { "G55" });
    w.line("M8");
    w.rapid(Some(p.x0 + p.w / 2.0), Some(p.y0), None);
    w.rapid(None, None, Some(p.clear));
    w.contour(&p);
    w.line("M9");
    w.line("G30");
    w.reset();
    w.line("T2 M6 G43 H2");
    w.line(&format!("S{} M3", p.spindle / 2));
    w.cycle(&p, "G98", p.cycle);
    w.line("M5 M9");
    w.line("G30");
    w.line("M30");
    w.raw("%");
    w.out.into_bytes()
}

/// PyCAM's EMC2 export: every modal code on its own line with a comment, `G61` exact path,
/// `;PYCAM` settings comments, four decimals with all three axes on every move.
fn pycam(k: usize) -> Vec<u8> {
    let p = Part::new(k, false);
    let mut w = W::new(Digits::Fixed(4), " ");
    w.modal_axes = false;
    w.raw("G40 (disable tool radius compensation)");
    w.raw("G49 (disable tool length compensation)");
    w.raw("G80 (cancel modal motion)");
    w.raw("G54 (select coordinate system 1)");
    w.raw("G90 (disable incremental moves)");
    w.raw("G21 (metric)");
    w.raw("G61 (exact path mode)");
    w.raw(&format!("F{:.5}", p.feed));
    w.raw(&format!("S{:.5}", p.spindle as f64));
    w.raw(";PYCAM_TOOLPATH_SETTINGS: START");
    w.raw(&format!(";[Tool]\n;shape = CylindricalCutter\n;radius = {:.1}", 1.5 + 0.5 * (k % 4) as f64));
    w.raw(";PYCAM_TOOLPATH_SETTINGS: END");
    w.raw("T1 M6");
    w.raw(&format!("G0 Z{:.4}", p.clear));
    w.raw("M3 (start spindle)");
    w.raw("G04 P3 (wait for 3 seconds)");
    w.rapid(Some(p.x0), Some(p.y0), Some(p.clear));
    let (x0, y0, x1, y1) = (p.x0, p.y0, p.x0 + p.w, p.y0 + p.h);
    let rows = 4 + k % 4;
    for i in 0..=rows {
        let y = y0 + (y1 - y0) * i as f64 / rows as f64;
        let z = -p.depth * (1.0 + 0.3 * ((i as f64) * 0.7).sin()) / 2.0;
        let (xa, xb) = if i % 2 == 0 { (x0, x1) } else { (x1, x0) };
        w.feed(Some(xa), Some(y), Some((z * 1e4).round() / 1e4), p.feed);
        w.feed(Some(xb), Some(y), Some((z * 1e4).round() / 1e4), p.feed);
    }
    w.rapid(Some(x0), Some(y1), Some(p.clear));
    w.raw("M5 (stop spindle)");
    w.raw("M2 (end program)");
    w.out.into_bytes()
}

/// HeeksCNC's emc2b post: a `(Created with ...)` comment, `G21`, `G90`, `G17`, `T1 M06`,
/// `G43H1` without a blank, moves with three decimals, `G02`/`G03` with I J, `M02`.
fn heekscnc(k: usize) -> Vec<u8> {
    let p = Part::new(k, false);
    let mut w = W::new(Digits::Fixed(3), " ");
    w.raw("(Created with emc2b post processor 2013/11/27 10:15)");
    w.raw(&format!("(HEEKS PROFILE {k})"));
    w.raw("G21");
    w.raw("G90");
    w.raw("G17");
    w.raw(&format!("(tool change to {}mm Slot Cutter)", 4 + k % 4));
    w.raw("T1 M06");
    w.raw("G43H1");
    w.raw(&format!("S{} M03", p.spindle));
    w.modal_g = false;
    let g = |s: &str| s.replace("G0 ", "G00 ").replace("G1 ", "G01 ").replace("G2 ", "G02 ").replace("G3 ", "G03 ");
    w.contour(&p);
    w.holes_expanded(&p);
    w.out = w.out.lines().map(|l| g(&format!("{l} "))).map(|l| l.trim_end().to_string() + "\n").collect();
    w.raw("M05");
    w.raw("M02");
    w.out.into_bytes()
}

/// A LinuxCNC program written by hand: named parameters, an `o-word` subroutine with arguments,
/// a `while` loop of passes, `;` comments, `G10 L2` setting G55, polar-free IJ arcs, `M2`.
fn linuxcnc_hand(k: usize) -> Vec<u8> {
    let d = 1.0 + 0.25 * (k % 4) as f64;
    let n = 2 + k % 3;
    let x = -30.0 + 5.0 * k as f64;
    format!(
        "; pocket corners, variant {k}\nG21 G90 G17 G40 G49 G64 P0.01\n#<_depth> = {d}\n#<_passes> = {n}\nT1 M6\nG43 H1\n\
         G10 L2 P2 X{x} Y{} Z0\nG55\no100 sub ; corner x y r\n  G0 X#1 Y#2\n  G0 Z2\n  G1 Z[-#<_depth> / #<_passes> * #4] F200\n\
         G3 X[#1 + #3] Y[#2 + #3] I#3 J0 F800\n  G0 Z5\no100 endsub\n#<i> = 1\no110 while [#<i> LE #<_passes>]\n\
         o100 call [10] [10] [{}] [#<i>]\n  o100 call [-20] [15] [4] [#<i>]\n  #<i> = [#<i> + 1]\no110 endwhile\nG0 Z20\nG54\nM2\n",
        -10.0 + 2.0 * k as f64,
        3 + k % 5
    )
    .into_bytes()
}

/// Fusion 360 for Mach3 with its subroutine option (as the Autodesk posts write subprograms: each
/// operation an `O1001`, `O1002` ... ending with `M99` after the main program's `M30`, called by
/// `M98 P..`): the contour's depth passes as an incremental step called with `L` (one pass each),
/// the drilling cycle in a subprogram of its own, called twice in one variant of three (two
/// parts at the same place: the program is expanded there).
fn fusion_mach3_subs(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 4 == 3);
    let mut w = W::new(Digits::Trim(if p.inch { 4 } else { 3 }, false), " ");
    let step = -p.depth / p.passes as f64;
    let (x0, y0, x1, y1) = (p.x0, p.y0, p.x0 + p.w, p.y0 + p.h);
    fusion_mach3_start(&mut w, &p, 2000 + k);
    w.rapid(Some(x0), Some(y0), None);
    w.line(&format!("G43 Z{} H1", w.num(p.clear)));
    w.reset();
    w.rapid(None, None, Some(0.0));
    w.line(&format!("M98 P1001 L{}", p.passes));
    w.line(&format!("G0 Z{}", w.num(p.clear)));
    w.line("M5");
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.raw("(DRILL1)");
    w.line("T2 M6");
    w.line(&format!("S{} M3", p.spindle / 2));
    w.line(&format!("G43 Z{} H2", w.num(p.clear)));
    w.line(if k % 3 == 0 { "M98 P1002 L2" } else { "M98 P1002" });
    w.line("M5");
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.line("M30");
    w.raw("O1001 (2D CONTOUR1)");
    w.reset();
    w.line(&format!("G91 G1 Z{} F{}", w.num(step), w.num(p.plunge)));
    w.line(&format!("G90 X{} F{}", w.num(x1), w.num(p.feed)));
    w.line(&format!("Y{}", w.num(y1)));
    w.line(&format!("X{}", w.num(x0)));
    w.line(&format!("Y{}", w.num(y0)));
    w.line("M99");
    w.raw("O1002 (DRILL1)");
    w.reset();
    w.cycle(&p, "G98", if matches!(p.cycle, Cycle::Tap) { Cycle::Peck } else { p.cycle });
    w.line("M99");
    w.raw("%");
    w.out.into_bytes()
}

/// A Haas program written at the machine with `M97` local subprograms (Haas manual, "M97 Local
/// Sub-Program Call"; hand-written Haas facing programs published in repositories): a comment
/// after every block's `;`, `G00;`/`G01;` lines that only set the mode, a facing pass as the
/// subprogram `N1000` stepping down in `G91` and cutting in `G90`, called `L` times, a second
/// local subprogram `N2000` for a spot-drilled hole pattern.
fn haas_m97(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 2 == 1);
    let w = W::new(Digits::Trim(if p.inch { 4 } else { 3 }, true), " ");
    let n = |v: f64| w.num(v);
    let (x0, x1, y0, y1) = (p.x0, p.x0 + p.w, p.y0, p.y0 + p.h);
    let stock = if p.inch { 0.02 } else { 0.5 };
    let passes = 2 + k % 4;
    let mut lines = vec![
        "%".to_string(),
        format!("O{:05} (FACE AND SPOT {k})", 3000 + k),
        "G20 G90 G17 G40 G80; (SAFE START)".replace("G20", units(&p)),
        "G54; (WORK OFFSET)".into(),
        "T1 M06; (FACE MILL)".into(),
        "G43 H01; (TOOL LENGTH)".into(),
        format!("M03 S{}; (SPINDLE ON)", p.spindle / 2),
        "G00; (RAPID)".into(),
        format!("Z{}; (SAFE Z)", n(p.clear)),
        format!("X{} Y{};", n(x0), n(y0)),
        format!("Z{};", n(stock * passes as f64)),
        format!("M97 P1000 L{passes}; (FACING, {passes} PASSES)"),
        "G00;".into(),
        format!("Z{};", n(p.clear)),
        "T2 M06; (SPOT DRILL)".into(),
        format!("G43 H02 Z{};", n(p.clear)),
        format!("M03 S{};", p.spindle),
        "M97 P2000; (SPOT HOLES)".into(),
        "G00;".into(),
        format!("Z{};", n(p.clear)),
        "M30;".into(),
        String::new(),
        "N1000; (FACING SUBROUTINE)".into(),
        "G91; (INCREMENTAL)".into(),
        format!("G00 Z-{};", n(stock)),
        "G90; (ABSOLUTE)".into(),
        "G01; (FEED)".into(),
        format!("X{} F{};", n(x1), n(p.feed)),
        "G00;".into(),
        format!("Y{};", n(y1)),
        "G01;".into(),
        format!("X{};", n(x0)),
        "G00;".into(),
        format!("Y{};", n(y0)),
        "M99;".into(),
        String::new(),
        "N2000; (SPOT DRILL PATTERN)".into(),
    ];
    let first = p.holes[0];
    lines.push(format!("G00 X{} Y{};", n(first[0]), n(first[1])));
    lines.push(format!("G98 G81 Z-{} R{} F{};", n(p.safe / 5.0), n(p.safe), n(p.plunge)));
    lines.extend(p.holes[1..].iter().map(|h| format!("X{} Y{};", n(h[0]), n(h[1]))));
    lines.extend(["G80;".to_string(), "M99;".into(), "%".into()]);
    let mut s = lines.join("\n");
    s.push('\n');
    if k % 3 == 2 {
        // a control that does not want the `;` (typed at a PC)
        s = s.replace(";\n", "\n").replace("; (", " (");
    }
    s.into_bytes()
}

/// A grbl job as a sender streams it (Universal G-code Sender, CNCjs and bCNC macros; the senders'
/// jog commands as published, `$J=G91 G21 X1.250 F300` and `$J=G91X10F100` without blanks): `$X`
/// (unlock) and `$H` (homing) first, the `$G`/`$#` reports, a jog to the part in `G90`, the Fusion
/// 360 grbl program, an incremental jog up at the end.
fn grbl_stream(k: usize) -> Vec<u8> {
    let p = Part::new(k, false);
    let mut w = W::new(Digits::Trim(3, false), " ");
    if k % 2 == 0 {
        w.raw("$X");
    }
    w.raw("$H");
    if k % 3 == 0 {
        w.raw("$G");
        w.raw("$#");
    }
    w.raw("G21 G90 G94");
    let (x, y) = (w.num(p.x0), w.num(p.y0));
    w.raw(&if k % 2 == 0 { format!("$J=G90 G21 X{x} Y{y} F3000") } else { format!("$J=G21G90X{x}Y{y}F3000") });
    w.raw("G17");
    w.raw(&format!("S{} M3", p.spindle));
    w.reset();
    w.rapid(None, None, Some(p.clear));
    if k % 2 == 1 {
        w.facing(&p);
    }
    w.contour(&p);
    w.holes_expanded(&p);
    w.raw("M5");
    w.raw(&if k % 2 == 0 { "$J=G91 G21 Z10 F1000".to_string() } else { "$J=G91G21Z10F1000".to_string() });
    w.raw("M30");
    w.out.into_bytes()
}

/// The SINUMERIK's unit codes: G70 inch, G71 mm.
fn siemens_units(p: &Part) -> &'static str {
    if p.inch {
        "G70"
    } else {
        "G71"
    }
}

/// Fusion 360 for the SINUMERIK 840D: the archive header `%_N_.._MPF` and `;$PATH=`, `;` tool
/// comments, `T1 D1` then `M6`, `CR=` arcs (or I J), `MCALL CYCLE81(RTP, RFP, SDIS, DP, )` or
/// `MCALL CYCLE83(...)` (chip breaking or swarf removal, in the post's 17 parameters) over the
/// holes and `MCALL`, or one direct `CYCLE82(...)` per hole with its dwell, `G0 SUPA Z0 D0` and
/// `M30` at the end.
fn fusion_siemens(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 4 == 3);
    let mut w = W::new(Digits::Trim(if p.inch { 5 } else { 4 }, false), " ");
    w.arcs = if k % 3 == 2 { ArcWords::Ij } else { ArcWords::Cr };
    w.raw(&format!("%_N_PART{k}_MPF"));
    w.raw(&format!(";$PATH=/_N_WKS_DIR/_N_PART{k}_WPD"));
    w.raw(&format!("; T1 D=6 CR=0 - ZMIN=-{} - FLAT END MILL", w.num(p.depth)));
    w.seq = Some((10, 2));
    w.line("G90 G94 G17 G40");
    w.line(siemens_units(&p));
    w.raw("; CONTOUR2D");
    w.line("T1 D1");
    w.line("M6");
    w.line(&format!("S{} M3", p.spindle));
    w.line("G54");
    w.line("M8");
    if k % 2 == 1 {
        w.line("CYCLE832(0.01,_ORI_ROUGH,1)");
    }
    w.rapid(Some(p.x0 + p.w / 2.0), Some(p.y0), None);
    w.rapid(None, None, Some(p.clear));
    w.contour(&p);
    w.line("M9");
    w.line("M5");
    w.reset();
    w.raw("; DRILL1");
    w.line("T2 D1");
    w.line("M6");
    w.line(&format!("S{} M3", p.spindle / 2));
    w.line("G54");
    let first = p.holes[0];
    w.rapid(Some(first[0]), Some(first[1]), None);
    w.rapid(None, None, Some(p.clear));
    w.line(&format!("F{}", w.num(p.plunge)));
    let (rtp, sdis, dp) = (w.num(p.clear), w.num(p.safe), w.num(-p.hole_depth));
    if k % 2 == 0 || k % 4 == 3 {
        // the post's chip breaking (VARI 0, _VRT its chip-break distance, _DIS1 0) and deep
        // drilling (VARI 1, here with the anticipation distance _DIS1 given): FDEP = RFP - peck, DAM 0
        let (peck, back) = (w.num(p.peck), w.num(p.peck / 5.0));
        w.line(&match k % 4 {
            0 => format!("MCALL CYCLE81({rtp}, 0, {sdis}, {dp}, )"),
            2 => format!("MCALL CYCLE83({rtp}, 0, {sdis}, {dp}, , -{peck}, , 0, , , 1, 0, , {peck}, {back}, 0, 0)"),
            _ => format!("MCALL CYCLE83({rtp}, 0, {sdis}, {dp}, , -{peck}, , 0, , , 1, 1, , {peck}, 0, 0, {back})"),
        });
        for h in &p.holes {
            w.line(&format!("X{} Y{}", w.num(h[0]), w.num(h[1])));
        }
        w.line("MCALL");
    } else {
        for h in &p.holes {
            w.line(&format!("G0 X{} Y{}", w.num(h[0]), w.num(h[1])));
            w.line(&format!("CYCLE82({rtp}, 0, {sdis}, {dp}, , 0.2)"));
        }
    }
    w.line("M5");
    w.line("G0 SUPA Z0 D0");
    w.line("M30");
    w.out.into_bytes()
}

/// The plate's contour of [`siemens_hand`] from the R parameters: inline (from its third line),
/// or as the subprogram files L10.SPF and CONTOUR.spf (the depth R10 grows by R6/2 at each pass).
const SIEMENS_CONTOUR: [&str; 11] = [
    "G1 Z=-R10 F=R8",
    "X=R3-R5 F=R9",
    "G3 X=R3 Y=R5 CR=R5",
    "G1 Y=R4-R5",
    "G3 X=R3-R5 Y=R4 CR=R5",
    "G1 X=R5",
    "G3 X0 Y=R4-R5 I0 J=-R5",
    "G1 Y=R5",
    "G3 X=R5 Y0 CR=R5",
    "G1 X=R3/2",
    "G0 Z=R11",
];

/// The subprogram files the corpus's SINUMERIK programs call (written on their search path).
pub fn siemens_subprograms() -> Vec<(&'static str, String)> {
    let body = SIEMENS_CONTOUR.join("\n");
    vec![
        ("L10.SPF", format!("%_N_L10_SPF\n;$PATH=/_N_SPF_DIR\nN10 R10=R10+R6/2\n{body}\nM17\n")),
        ("CONTOUR.spf", format!("PROC CONTOUR ; the plate's contour\nR10=R10+R6/2\n{body}\nRET\n")),
    ]
}

/// A hand-written 840D program: the plate's corner and size in R parameters, `TRANS` to its corner,
/// `X=`/`Y=` values and `CR=R5` arcs computed from them (inline, or in a subprogram file `L10` or
/// `CONTOUR` run twice), the holes from the plate's middle after
/// `ATRANS` in a modal `CYCLE82` whose depth is DPR from the surface, `G4 F` dwells, Latin-1 or
/// UTF-8 comments, CR LF line ends in some.
fn siemens_hand(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 5 == 4);
    let mut w = W::new(Digits::Trim(if p.inch { 5 } else { 4 }, false), " ");
    if k % 2 == 0 {
        w.raw(&format!("%_N_PLATTE{k}_MPF"));
        w.raw(&format!(";$PATH=/_N_WKS_DIR/_N_PLATTE{k}_WPD"));
    }
    w.raw(&format!("; Platte {k} - Fräser Ø6, Bohrer Ø5"));
    w.seq = if k % 3 == 1 { None } else { Some((10, 10)) };
    w.line(&format!("G17 {} G90 G40 G94", siemens_units(&p)));
    w.line(&format!("R1={} R2={} R3={} R4={}", w.num(p.x0), w.num(p.y0), w.num(p.w), w.num(p.h)));
    w.line(&format!("R5={} R6={} R7={} R11={}", w.num(p.r), w.num(p.depth), w.num(p.hole_depth), w.num(p.safe)));
    w.line("T1 D1 M6");
    w.line(&format!("G54 S{} M3", p.spindle));
    w.line("TRANS X=R1 Y=R2 ; corner of the plate");
    w.line(&format!("G0 X=R3/2 Y0 Z{}", w.num(p.clear)));
    w.line(&format!("Z{}", w.num(p.safe)));
    let (f, plunge) = (w.num(p.feed), w.num(p.plunge));
    if k % 3 == 2 {
        w.line(&format!("G1 Z=-R6 F{plunge}"));
        w.line(&format!("X=R3-R5 F{f}"));
        for l in &SIEMENS_CONTOUR[2..] {
            w.line(l);
        }
    } else {
        // the contour in a subprogram file, in two passes of half the depth
        w.line(&format!("R8={plunge} R9={f} R10=0"));
        w.line(if k % 3 == 0 { "L10 P2 ; contour" } else { "CONTOUR P2" });
    }
    w.line(&format!("G0 Z{}", w.num(p.clear)));
    w.line("G4 F1 ; chips");
    w.line("T2 D1 M6");
    w.line("ATRANS X=R3/2 Y=R4/2 ; the middle");
    w.line(&format!("F{plunge}"));
    w.line(&format!("MCALL CYCLE82({}, 0, {}, , R7, 0.5)", w.num(p.clear), w.num(p.safe)));
    let (mx, my) = (p.x0 + p.w / 2.0, p.y0 + p.h / 2.0);
    for h in &p.holes {
        w.line(&format!("G0 X{} Y{}", w.num(h[0] - mx), w.num(h[1] - my)));
    }
    w.line("MCALL");
    w.line("TRANS");
    w.line("G0 SUPA Z0 D0");
    w.line("M30");
    match k % 4 {
        1 => latin1(&w.out),
        3 => crlf(w.out),
        _ => w.out.into_bytes(),
    }
}

/// A hand-written 840D program in the habits of published shop programs and cycles (docs/nc.md):
/// `DEF INT`/`REAL`/`BOOL` variables at the top, the pocket's passes in a `FOR` loop over the
/// depth, a finishing `IF`-`ELSE`-`ENDIF` on a BOOL with an `AR=` arc, a row of holes in a `LOOP`
/// left by `IF ... GOTOF` to a label, a `WHILE` loop or a `REPEAT`-`UNTIL` loop, a label alone on
/// its block, a `GOTOF` over a block, R parameters beside the variables.
fn siemens_flow(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 5 == 4);
    let mut w = W::new(Digits::Trim(if p.inch { 5 } else { 4 }, false), " ");
    w.raw(&format!("%_N_FLOW{k}_MPF"));
    w.raw(&format!(";$PATH=/_N_WKS_DIR/_N_FLOW{k}_WPD"));
    w.raw(&format!("DEF INT PASS, PASSES={}, HOLE", 2 + k % 2));
    let (x0, y0, width, height) = (w.num(p.x0), w.num(p.y0), w.num(p.w), w.num(p.h));
    w.raw(&format!("DEF REAL DEPTH={}, STEP, CX={x0}, CY={y0}, WIDTH={width}, HEIGHT={height}", w.num(p.depth)));
    w.raw(&format!("DEF BOOL FINISH={}", if k % 2 == 0 { "TRUE" } else { "FALSE" }));
    w.seq = if k % 3 == 1 { None } else { Some((10, 10)) };
    w.line(&format!("G17 {} G90 G40 G94", siemens_units(&p)));
    w.line("T1 D1 M6");
    w.line(&format!("G54 S{} M3", p.spindle));
    w.line("STEP=DEPTH/PASSES");
    w.line(&format!("G0 X=CX Y=CY Z{}", w.num(p.clear)));
    w.line(&format!("Z{}", w.num(p.safe)));
    let (f, plunge) = (w.num(p.feed), w.num(p.plunge));
    w.line("FOR PASS=1 TO PASSES ; depth passes");
    w.line(&format!("G1 Z=-STEP*PASS F{plunge}"));
    w.line(&format!("X=CX+WIDTH F{f}"));
    w.line("Y=CY+HEIGHT");
    w.line("X=CX");
    w.line("Y=CY");
    w.line("ENDFOR");
    w.line("IF FINISH");
    w.line("G1 X=CX+WIDTH/2 Y=CY+HEIGHT/4");
    w.line(&format!("G3 X=CX+WIDTH/2 Y=CY+HEIGHT*3/4 AR={}", 90 + 30 * (k % 4)));
    w.line("ELSE");
    w.line(&format!("G0 Z{}", w.num(p.safe)));
    w.line("ENDIF");
    w.line(&format!("G0 Z{}", w.num(p.clear)));
    w.line("T2 D1 M6");
    let n = p.holes.len();
    let row = format!("G0 X=CX+WIDTH*(HOLE+1)/{} Y=CY+HEIGHT/2", w.num(n as f64 + 1.0));
    let drill = [format!("G1 Z=-{} F{plunge}", w.num(p.hole_depth)), format!("G0 Z{}", w.num(p.safe))];
    w.line("HOLE=0");
    match k % 3 {
        0 => {
            w.line("LOOP");
            w.line(&format!("IF HOLE >= {n} GOTOF ROW_DONE"));
            w.line(&row);
            drill.iter().for_each(|l| w.line(l));
            w.line("HOLE=HOLE+1");
            w.line("ENDLOOP");
            w.line("ROW_DONE:");
        }
        1 => {
            w.line(&format!("WHILE HOLE < {n}"));
            w.line(&row);
            drill.iter().for_each(|l| w.line(l));
            w.line("HOLE=HOLE+1");
            w.line("ENDWHILE");
        }
        _ => {
            w.line("REPEAT");
            w.line(&row);
            drill.iter().for_each(|l| w.line(l));
            w.line("HOLE=HOLE+1");
            w.line(&format!("UNTIL (HOLE >= {n}) OR (HOLE > 99)"));
        }
    }
    w.line("R1=1");
    w.line("IF R1==1 GOTOF SKIP");
    w.line("G0 X0 Y0 ; never run");
    w.line(&format!("SKIP: G0 Z{}", w.num(p.clear)));
    w.line("G0 SUPA Z0 D0");
    w.line("M30");
    match k % 4 {
        3 => crlf(w.out),
        _ => w.out.into_bytes(),
    }
}

/// Fusion 360 for Fadal (`fadal.cps`, format 2 with E numbers): `%`, `O1101 (NAME)`, the tool
/// list, `G90 G94 G17`, the units, a blank line before each operation, `T1 M6`, the dwell of three
/// spindle turns `G4 P..` (ms), `G90 G0 E.. X.. Y..`, `G0 G43 Z.. H..`, `G17` around operations,
/// `M1`, a `G0` alone before the cycle, `G98 G90 G81/G83/G73/G85 .. R0+5.000` (the R plane as the
/// R0 word with its sign, 3 or 4 decimals), `G28 G91 Z0.` / `G90`, `G90 G0` then `G53 X0. Y0.`.
fn fusion_fadal(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 4 == 3);
    let decimals = if p.inch { 4 } else { 3 };
    let mut w = W::new(Digits::Trim(decimals, true), " ");
    let (e1, e2) = ([1, 2, 3][k % 3], [7, 8, 2, 4][k % 4]);
    w.raw("%");
    w.raw(&format!("O{:04} (FADAL {k})", 1100 + k));
    w.raw(&format!("(T1  D=6. CR=0. - ZMIN=-{} - FLAT END MILL)", w.num(p.depth)));
    w.raw(&format!("(T2  D=5. CR=0. TAPER=118DEG - ZMIN=-{} - DRILL)", w.num(p.hole_depth)));
    w.seq = Some((10, 5));
    w.line("G90 G94 G17");
    w.line(units(&p));
    w.raw("");
    w.raw("(2D CONTOUR1)");
    w.line("T1 M6");
    w.line(&format!("S{} M3", p.spindle));
    w.line(&format!("G4 P{}", (3.0 * 60.0 / f64::from(p.spindle) * 1000.0).round()));
    w.line("G17");
    w.line(&format!("G90 G0 E{e1} X{} Y{}", w.num(p.x0 + p.w / 2.0), w.num(p.y0)));
    w.line(&format!("G0 G43 Z{} H1", w.num(p.clear)));
    w.line("M8");
    w.reset();
    w.rapid(Some(p.x0 + p.w / 2.0), Some(p.y0), Some(p.clear));
    w.contour(&p);
    w.line("G17");
    w.line("M9");
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.reset();
    w.raw("");
    w.raw("(DRILL1)");
    w.line("M1");
    w.line("T2 M6");
    w.line(&format!("S{} M3", p.spindle / 2));
    w.line("G17");
    w.line(&format!("G90 G0 E{e2} X{} Y{}", w.num(p.holes[0][0]), w.num(p.holes[0][1])));
    w.line(&format!("G0 G43 Z{} H2", w.num(p.clear)));
    w.line("M8");
    w.line("G0");
    w.reset();
    let cycle = if p.cycle == Cycle::Tap { Cycle::Drill } else { p.cycle };
    w.cycle(&p, "G98 G90", cycle);
    w.line("G17");
    w.line("M9");
    w.line("G28 G91 Z0.");
    w.line("G90");
    w.line("G90 G0");
    w.line("G53 X0. Y0.");
    w.line("M30");
    w.raw("%");
    // the R plane as fadal.cps writes it: `R0` and the value with its sign and all its decimals
    let r = format!(" R{}", w.num(p.safe));
    let r0 = format!(" R0{:+.decimals$}", p.safe);
    w.out.replace(&r, &r0).into_bytes()
}

/// A Fadal program written by hand with macro statements: `E1`, `# CLEAR`, depth passes of an
/// incremental square made a loop by `#:PASS` ... `# IF V1 LT V2 THEN GOTO :PASS`, `# PRINT`, a
/// jump forward over a block when there are more than two passes, and in some variants an `M98`
/// subprogram of incremental moves run twice (its `O` program after `M30`).
fn fadal_macro(k: usize) -> Vec<u8> {
    let p = Part::new(k, k % 5 == 4);
    let mut w = W::new(Digits::Trim(if p.inch { 4 } else { 3 }, true), " ");
    let step = ((p.depth / p.passes as f64) * 1e4).round() / 1e4;
    w.raw("%");
    w.seq = Some((1, 1));
    w.line(&format!("O{} (FADAL MACRO {k})", 7100 + k));
    w.line(&format!("G90 G80 G40 G17 {}", units(&p)));
    w.line("M6 T1");
    w.line(&format!("G0 E1 X{} Y{} S{} M3", w.num(p.x0), w.num(p.y0), p.spindle));
    w.line(&format!("G43 H1 Z{} M8", w.num(p.clear)));
    w.line(&format!("G0 Z{}", w.num(p.safe)));
    w.line(&format!("G1 Z0. F{}", w.num(p.plunge)));
    w.seq = None;
    let lines = [
        "# CLEAR".to_string(),
        "# V1 = 0".into(),
        format!("# V2 = {}", p.passes),
        "#:PASS".into(),
        format!("G91 G1 Z-{} F{}", w.num(step), w.num(p.plunge)),
        format!("X{} F{}", w.num(p.w), w.num(p.feed)),
        format!("Y{}", w.num(p.h)),
        format!("X-{}", w.num(p.w)),
        format!("Y-{}", w.num(p.h)),
        "G90".into(),
        "# V1 = V1 + 1".into(),
        "# IF V1 LT V2 THEN GOTO :PASS".into(),
        "# PRINT \"PASSES DONE \", V1".into(),
        format!("G0 Z{}", w.num(p.clear)),
    ];
    for l in lines {
        w.raw(&l);
    }
    if k % 3 == 0 {
        w.raw(&format!("M98 P{} L2", 7200 + k));
    }
    w.raw("# IF V2 GT 2 THEN GOTO :SKIP");
    w.raw(&format!("G0 X{} Y{}", w.num(p.x0 + p.w), w.num(p.y0)));
    w.raw("#:SKIP");
    w.raw("G0 G91 G28 Z0.");
    w.raw("G90");
    w.raw("M30");
    if k % 3 == 0 {
        w.raw(&format!("O{} (STEP)", 7200 + k));
        w.raw(&format!("G91 G0 X{}", w.num(p.peck)));
        w.raw(&format!("G1 Z-{} F{}", w.num(p.peck), w.num(p.plunge)));
        w.raw(&format!("G0 Z{}", w.num(p.peck)));
        w.raw("G90");
        w.raw("M99");
    }
    w.raw("%");
    w.out.into_bytes()
}
