//! The miniaturisation case of Zhu 2008 appendix B.2: a three-axis machine `P_T G_R X Y Z T_L`
//! (structure `wbXYZt`: the part on the bed, X on the bed, Y on X, Z on Y, the tool on Z) scaled to
//! cubic parts of 10 to 300 mm, with the 21 components of B.2 equal on every axis.
//!
//! Assumptions where the appendix is silent (its figures are lost): the machine is the part scaled,
//! travels `[0, L]` on every axis and a tool `L` long (so every lever arm scales with the part); the
//! errors are 1 um (linear) and 1 arcsec = 4.848 urad (angular, squareness), the units of the
//! appendix's Figure B.7; the poses are a 5 x 5 x 5 grid over the travel. The homogenisation length is
//! 1 m for every size: machines of every size made with the same technology, where a tolerance costs
//! what its absolute value costs (scaling it with the part would make every size the same machine).
//! The allocation keeps the relative accuracy constant: a root-sum-square target of `L x` the relative
//! accuracy per direction, equal costs `1 / e^2`, lower limits 0.01 um and 0.05 urad.

use super::allocate::{allocate, Allocation, AllocationOptions, Stack, Target};
use super::analysis::{analyse, Analysis};
use super::components::{bind, default_components};
use super::cost::CostModel;
use super::global::GeneticOptions;
use super::poses::volume_grid;
use super::spec::{BudgetSpec, KindValues};
use crate::error::Error;
use crate::machine::Machine;
use crate::model::{Frame, Setup};

/// The part sizes of the appendix (mm).
pub const SIZES: [f64; 6] = [10.0, 20.0, 50.0, 100.0, 200.0, 300.0];
/// 1 arcsec in urad.
pub const ARCSEC_URAD: f64 = 4.848_136_811_095_36;

/// The machine of the case for parts of `size` mm.
pub fn machine(size: f64) -> Machine {
    let text = format!(
        "name = \"three-axis machine for {size} mm parts\"\nsource = \"Zhu (2008) appendix B.2\"\nstructure = \"wbXYZt\"\n[axes]\n\
         X = {{ kind = \"linear\", direction = [1, 0, 0], range = [0, {size}] }}\n\
         Y = {{ kind = \"linear\", direction = [0, 1, 0], range = [0, {size}] }}\n\
         Z = {{ kind = \"linear\", direction = [0, 0, 1], range = [0, {size}] }}\n[tool]\npoint = [0, 0, {size}]\n"
    );
    Machine::from_toml_str(&text, "miniaturisation").expect("a valid machine")
}

/// The 21 components with equal tolerances and a 1 m homogenisation length.
pub fn spec(machine: &Machine, tolerances: KindValues) -> BudgetSpec {
    let components = bind(machine, &default_components(machine), &[1000.0; 3]).expect("the standard set binds");
    let cost = CostModel::uniform(&components, 1.0, 2.0, [0.01, 0.05, 0.05]);
    let tolerances = components.iter().map(|c| tolerances.of(c.kind)).collect();
    BudgetSpec { components, tolerances, cost }
}

/// One part size of the case.
#[derive(Clone, Debug)]
pub struct SizeCase {
    pub size: f64,
    /// Forward analysis with the equal errors.
    pub analysis: Analysis,
    /// The allocation for a constant relative accuracy.
    pub allocation: Allocation,
    /// The forward analysis of the allocated tolerances (its shares are B.20-B.21).
    pub allocated: Analysis,
}

/// Runs the case for `sizes` (mm) with the errors `tolerances` and a relative accuracy (target
/// per direction over part size).
pub fn run(sizes: &[f64], tolerances: KindValues, relative_accuracy: f64, genetic: GeneticOptions) -> Result<Vec<SizeCase>, Error> {
    let mut out = Vec::new();
    for &size in sizes {
        if !(size.is_finite() && size > 0.0) {
            return Err(Error::input(format!("part size {size} mm must be a positive length")));
        }
        let m = machine(size);
        let spec = spec(&m, tolerances);
        let user = volume_grid(&m, 5, &[])?;
        let mut poses = vec![0.0; user.len()];
        for (u, q) in user.chunks(3).zip(poses.chunks_mut(3)) {
            m.pose_to_internal(u, q);
        }
        let setup = Setup::of_machine(&m);
        let analysis = analyse(&m, &spec, &poses, &setup, Frame::Workpiece)?;
        let target = relative_accuracy * size * 1000.0;
        let options = AllocationOptions { stack: Stack::Rss, target: Target::PerDirection([target; 3]), genetic };
        let allocation = allocate(&spec, &analysis.sensitivity, &options)?;
        let allocated_spec = spec.with_tolerances(allocation.tolerances.clone());
        let allocated = analyse(&m, &allocated_spec, &poses, &setup, Frame::Workpiece)?;
        out.push(SizeCase { size, analysis, allocation, allocated });
    }
    Ok(out)
}
