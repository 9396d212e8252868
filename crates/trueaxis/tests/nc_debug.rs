mod nc_common;
use nc_common::oracle::Oracle;
use nc_common::rs274::rs274;
use trueaxis::compensate::nc::*;
use trueaxis::compensate::Corrector;
use trueaxis::errors::ErrorModel;
use trueaxis::machine::Machine;
#[test]
fn debug_one() {
    let path = std::env::var("NCDBG").unwrap();
    let rs = rs274().unwrap();
    let text = std::fs::read_to_string("../../examples/machines/vmc3.toml").unwrap();
    let text = text.replace("range = [-400, 400]", "range = [-3000, 3000]").replace("range = [-250, 250]", "range = [-3000, 3000]").replace("range = [-400, 0]", "range = [-3000, 3000]");
    let machine = Machine::from_toml_str(&text, "m").unwrap();
    let errors = ErrorModel::load("../../examples/errors/vmc3.toml", &machine).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let tools: String = (1..=20).map(|n| format!("T{n} P{n} Z{:.3} D{:.3} ;tool {n}\n", 0.25 * n as f64, 0.05 * n as f64)).collect();
    std::fs::write(dir.path().join("t.tbl"), &tools).unwrap();
    let src = std::fs::read_to_string(&path).unwrap();
    std::fs::write(dir.path().join("p.ngc"), &src).unwrap();
    let mut options = NcOptions::new(&machine);
    options.setup.machine_inch = true;
    options.setup.rs274_tool_change = true;
    options.setup.tools = ToolTable::parse(&tools, "t").unwrap();
    let corrector = Corrector::new(&machine, &errors);
    let r = correct_program(&corrector, &src, "p", &options, &[]).unwrap();
    std::fs::write("/tmp/t19/dbg_corrected.ngc", &r.text).unwrap();
    std::fs::write(dir.path().join("c.ngc"), &r.text).unwrap();
    let o = rs.run(dir.path(), "p.ngc", Some("t.tbl")).unwrap();
    let c = rs.run(dir.path(), "c.ngc", Some("t.tbl")).unwrap();
    let oracle = Oracle { machine: &machine, errors: &errors, temperatures: vec![] };
    let k: usize = std::env::var("NCMOVE").map(|v| v.parse().unwrap()).unwrap_or(0);
    if k > 0 { for i in k.saturating_sub(3)..(k+2).min(o.len()) { println!("orig {} {:?}\ncorr {} {:?}", i+1, o[i], i+1, c.get(i)); } }
    println!("{:?}", oracle.compare(&o, &c, &[0.0; 3], 0.05, 1.05, &[]));
}
