//! `trueaxis ballbar tmbb-setup`: choosing and checking the setup of the two-length rotary-table test.

use crate::output::{self, print};
use crate::Failure;
use anyhow::anyhow;
use serde_json::json;
use trueaxis::identify::tmbb::TmbbSetup;
use trueaxis::identify::tmbb_setup::{rx_choice, setup_dimension_sensitivity, TableErrors};

// The dimensions of the two-length test (mm), the defaults those of Zhu (2008): the table-ball
// radius R_x and its height R_z, the bar lengths L1 and L2 (`ballbar tmbb` and `ballbar tmbb-setup`).
#[derive(clap::Args)]
pub struct SetupDimensions {
    #[arg(long, default_value_t = 71.8420)]
    pub rx: f64,
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub rz: f64,
    #[arg(long, default_value_t = 90.850)]
    pub l1: f64,
    #[arg(long, default_value_t = 217.952)]
    pub l2: f64,
}

impl SetupDimensions {
    /// The setup these dimensions give.
    pub fn setup(&self) -> TmbbSetup {
        TmbbSetup { rx: self.rx, rz: self.rz, l1: self.l1, l2: self.l2 }
    }
}

/// Plan the two-length telescopic ballbar test of a rotary table: for table-ball radii R_x over a
/// range, the standard uncertainty of the table tilts E_x, E_y and the axial error D_z per bar noise
/// (and the condition numbers, which depend on units); and how much the estimates move when the
/// setup dimensions R_x, R_z or the spindle height H are off.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  trueaxis ballbar tmbb-setup\n  \
trueaxis ballbar tmbb-setup --rx-scan 20:85:5 --deviations 0.1,0.5,1 --noise 0.5 --json\n\n\
Defaults: the bars and radius of the published two-length test (L1 = 90.850, L2 = 217.952 mm,\n\
R_x = 71.842 mm), one turn every 10 deg. The R_x column to choose by is u: it does not depend on units,\n\
the condition numbers do. The deviation table uses the true errors --ex, --ey (arcsec) and --dz (um).")]
pub struct TmbbSetupArgs {
    #[command(flatten)]
    dimensions: SetupDimensions,
    /// Table-ball radii FROM:TO:STEP (mm); every radius must stay below L1.
    #[arg(long)]
    rx_scan: Option<String>,
    /// Setup deviations (mm) applied to R_x, R_z and H in turn.
    #[arg(long, value_delimiter = ',', default_value = "0.1,0.5,1")]
    deviations: Vec<f64>,
    /// Standard deviation of the bar readings (um).
    #[arg(long, default_value_t = 1.0)]
    noise: f64,
    /// Table angle step (deg) over one turn.
    #[arg(long, default_value_t = 10.0)]
    step: f64,
    /// True table tilts (arcsec) and axial error (um) for the deviation table.
    #[arg(long, default_value_t = 8.0, allow_hyphen_values = true)]
    ex: f64,
    #[arg(long, default_value_t = 7.4, allow_hyphen_values = true)]
    ey: f64,
    #[arg(long, default_value_t = 2.7, allow_hyphen_values = true)]
    dz: f64,
    #[arg(long)]
    json: bool,
}

fn scan(text: &str, l1: f64) -> Result<Vec<f64>, Failure> {
    let bad = || Failure::input(anyhow!("--rx-scan `{text}`: give FROM:TO:STEP in mm with 0 < FROM <= TO < L1 = {l1} and STEP > 0"));
    let v: Vec<f64> = text.split(':').map(|s| s.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad())?;
    let [from, to, step] = v[..] else { return Err(bad()) };
    if !(from > 0.0 && to >= from && to < l1 && step > 0.0 && (to - from) / step <= 10_000.0) {
        return Err(bad());
    }
    Ok((0..=((to - from) / step + 1e-9).floor() as usize).map(|i| from + step * i as f64).collect())
}

pub fn run(a: TmbbSetupArgs) -> Result<(), Failure> {
    let setup = a.dimensions.setup();
    setup.heights().map_err(Failure::input)?;
    if !(a.noise.is_finite() && a.noise > 0.0 && a.noise <= 1000.0) {
        return Err(Failure::input(anyhow!("--noise {}: give the bar noise in um, above 0 and at most 1000", a.noise)));
    }
    if !(a.step.is_finite() && a.step >= 0.1 && a.step <= 90.0) {
        return Err(Failure::input(anyhow!("--step {}: give the table angle step in deg, 0.1 to 90", a.step)));
    }
    if let Some(d) = a.deviations.iter().find(|d| !(d.is_finite() && d.abs() <= 10.0)) {
        return Err(Failure::input(anyhow!("--deviations: {d} mm; give deviations of at most 10 mm")));
    }
    let angles: Vec<f64> = (0..(360.0 / a.step).round() as usize).map(|i| (i as f64 * a.step).to_radians()).collect();
    let radii = match &a.rx_scan {
        Some(t) => scan(t, a.dimensions.l1)?,
        None => {
            let top = (0.95 * a.dimensions.l1 / 5.0).floor() * 5.0;
            (1..=(top / 5.0) as usize).map(|i| 5.0 * i as f64).chain([a.dimensions.rx]).collect()
        }
    };
    let choices = rx_choice(&setup, &angles, &radii, a.noise * 1e-3).map_err(Failure::of)?;
    let arcsec = std::f64::consts::PI / 180.0 / 3600.0;
    let truth = TableErrors { ex: a.ex * arcsec, ey: a.ey * arcsec, dz: a.dz * 1e-3, ..Default::default() };
    let deviations = setup_dimension_sensitivity(&setup, &angles, &truth, &a.deviations).map_err(Failure::of)?;
    if a.json {
        let rx: Vec<_> = choices
            .iter()
            .map(|c| {
                json!({"rx_mm": c.rx, "height_difference_mm": round(c.height_difference, 4),
                       "condition_number": {"mm_rad": round(c.cond_mm_rad, 4), "m_rad": round(c.cond_m_rad, 4), "unit_columns": round(c.cond_unit_columns, 4)},
                       "u_ex_urad": round(c.u_ex * 1e6, 4), "u_ey_urad": round(c.u_ey * 1e6, 4), "u_dz_um": round(c.u_dz * 1e3, 4)})
            })
            .collect();
        let dev: Vec<_> = deviations
            .iter()
            .map(|d| {
                json!({"dimension": d.dimension, "deviation_mm": d.deviation_mm, "ex_urad": round(d.ex * 1e6, 4),
                            "ey_urad": round(d.ey * 1e6, 4), "dz_um": round(d.dz * 1e3, 4)})
            })
            .collect();
        let doc = json!({"l1_mm": a.dimensions.l1, "l2_mm": a.dimensions.l2, "rz_mm": a.dimensions.rz, "noise_um": a.noise, "angles": angles.len(), "rx": rx, "setup_deviations": dev});
        return output::json(&doc);
    }
    let mut out = format!(
        "Two-length rotary-table test, L1 = {} mm, L2 = {} mm, {} angles, bar noise {} um\n{:>8} {:>9} {:>10} {:>9} {:>9} {:>10} {:>10} {:>9}\n",
        a.dimensions.l1,
        a.dimensions.l2,
        angles.len(),
        a.noise,
        "R_x mm",
        "H2-H1 mm",
        "cond mm/rad",
        "cond m/rad",
        "cond unit",
        "u(E_x) urad",
        "u(E_y) urad",
        "u(D_z) um"
    );
    for c in &choices {
        out.push_str(&format!(
            "{:>8.3} {:>9.3} {:>10.2} {:>9.2} {:>9.3} {:>10.3} {:>10.3} {:>9.3}\n",
            c.rx,
            c.height_difference,
            c.cond_mm_rad,
            c.cond_m_rad,
            c.cond_unit_columns,
            c.u_ex * 1e6,
            c.u_ey * 1e6,
            c.u_dz * 1e3
        ));
    }
    out.push_str(&format!(
        "setup dimensions off (R_x = {} mm; true E_x {} arcsec, E_y {} arcsec, D_z {} um): estimate minus truth\n{:>10} {:>8} {:>12} {:>12} {:>10}\n",
        a.dimensions.rx, a.ex, a.ey, a.dz, "dimension", "off mm", "E_x urad", "E_y urad", "D_z um"
    ));
    for d in &deviations {
        out.push_str(&format!(
            "{:>10} {:>8} {:>12.4} {:>12.4} {:>10.3}\n",
            d.dimension,
            d.deviation_mm,
            d.ex * 1e6,
            d.ey * 1e6,
            d.dz * 1e3
        ));
    }
    out.push_str("a height error of either ball is an axial offset of the table: D_z takes it one for one\n");
    print(&out)
}

/// `v` rounded to `digits` decimals (the values of the JSON document).
fn round(v: f64, digits: i32) -> f64 {
    let f = 10f64.powi(digits);
    (v * f).round() / f
}
