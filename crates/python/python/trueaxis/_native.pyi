"""Type stubs of the extension module trueaxis._native (units: mm, deg, um, urad, degC, s)."""

from os import PathLike
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import results

_Path = Union[str, PathLike[str]]
_Point = Sequence[float]
_Progress = Callable[[int, int], Any]
_Chunk = Tuple[int, int, int]
_Array = npt.NDArray[np.float64]

__version__: str
PREDICTION_COLUMNS: List[str]
PREDICTION_COLUMNS_WITH_DL: List[str]
PREDICTION_UNITS: List[str]
PREDICTION_UNITS_WITH_DL: List[str]
"""Columns of a prediction: dx dy dz (um), drx dry drz (urad), dL (um)."""
BLOCK: int
"""Trials per random-number stream (a Monte Carlo chunk is a whole number of blocks)."""

class TrueaxisError(Exception):
    """An error of trueaxis; the message is the command line's."""

class InputError(TrueaxisError):
    """Bad input: a file, parameter or value (the command line's exit status 2)."""

class ComputationError(TrueaxisError):
    """A failed computation, e.g. a rank-deficient identification (exit status 1)."""

class ResourceError(TrueaxisError):
    """The environment failed, not the input: a full disk or quota, a permission, a read-only file system, a device error, memory (the command line's exit status 3)."""

class TrueaxisWarning(UserWarning):
    """A warning or note the command line prints on stderr (plausibility findings, corrections applied)."""

class Machine:
    """An immutable machine description; positions in mm (linear) and deg (rotary)."""
    @staticmethod
    def from_file(path: _Path) -> Machine: ...
    @staticmethod
    def from_toml(text: str, origin: str = "<machine>") -> Machine: ...
    @staticmethod
    def from_dict(d: Mapping[str, Any]) -> Machine: ...
    @property
    def name(self) -> str: ...
    @property
    def axes(self) -> str:
        """Axis letters in the order of the pose columns, e.g. "XYZAC"."""
    @property
    def units(self) -> List[str]: ...
    @property
    def tool_point(self) -> _Point:
        """Tool point at home in the machine frame (mm)."""
    @property
    def toml(self) -> str: ...
    def read_poses(self, path: _Path) -> _Array:
        """(N, axes) positions in mm and deg from a pose CSV."""
    def predict(
        self,
        errors: Errors,
        poses: _Array,
        *,
        tool_point: Optional[_Point] = None,
        work_point: Optional[_Point] = None,
        frame: str = "workpiece",
        temperatures: Optional[_Array] = None,
        directions: Optional[npt.ArrayLike] = None,
        with_dl: bool = False,
        out: Optional[_Array] = None,
    ) -> _Array:
        """Volumetric error at (N, axes) poses (mm, deg): (N, 6) dx dy dz in um, drx dry drz in
        urad, the columns PREDICTION_COLUMNS (N, 7 with dL in um when with_dl:
        PREDICTION_COLUMNS_WITH_DL); exact chain, batch kernel writing the array in place, GIL
        released. Any array-like of numbers is converted to float64. temperatures: (N, sensors)
        degC in the order of errors.sensors; directions: (N, axes) of -1, 0, +1 (e.g. int8), the
        direction of motion of each axis (0 at rest; without directions every axis is at rest and
        EXX+/EXX- give their mean). out: a C-contiguous float64 (N, 6 or 7) array written and returned."""
    def predict_file(
        self,
        errors: Errors,
        poses: _Path,
        *,
        tool_point: Optional[_Point] = None,
        work_point: Optional[_Point] = None,
        frame: str = "workpiece",
    ) -> results.Prediction:
        """The document of `trueaxis predict --json` for a pose CSV."""

class Errors:
    """The error model of a machine (um, urad)."""
    @staticmethod
    def from_file(path: _Path, machine: Machine) -> Errors: ...
    @staticmethod
    def from_toml(text: str, machine: Machine, origin: str = "<errors>") -> Errors: ...
    @staticmethod
    def from_dict(d: Mapping[str, Any], machine: Machine) -> Errors: ...
    @staticmethod
    def zero(machine: Machine) -> Errors: ...
    @property
    def sensors(self) -> List[str]:
        """Temperature sensors (T:<sensor>) the model needs, in order (degC)."""
    @property
    def toml(self) -> str: ...

class Campaign:
    """A measurement campaign: unknowns and measurements with their data files."""
    @staticmethod
    def from_file(path: _Path, machine: Machine) -> Campaign: ...
    @staticmethod
    def from_toml(text: str, machine: Machine, base_dir: _Path = ".", origin: str = "<campaign>") -> Campaign: ...
    @staticmethod
    def from_dict(d: Mapping[str, Any], machine: Machine, base_dir: _Path = ".") -> Campaign: ...
    @property
    def parameters(self) -> List[str]: ...
    @property
    def records(self) -> int: ...

class Identification:
    """Identified values, uncertainties (parameter units: um, urad, um/mm^k) and residuals (um)."""
    @property
    def names(self) -> List[str]: ...
    @property
    def units(self) -> List[str]: ...
    @property
    def values(self) -> _Array: ...
    @property
    def std_uncertainty(self) -> _Array:
        """NaN for a parameter in an unidentifiable combination."""
    @property
    def covariance(self) -> _Array: ...
    @property
    def residuals(self) -> _Array: ...
    def to_dataframe(self) -> Any:
        """pandas DataFrame: name, unit, value, std_uncertainty per unknown (pandas optional)."""
    def to_dict(self) -> Dict[str, Any]:
        """The document of `trueaxis identify --json`."""
    def errors_toml(self) -> str:
        """The error-values file `trueaxis identify --out` writes."""
    def errors(self) -> Errors: ...

def identify(
    machine: Machine,
    campaign: Campaign,
    *,
    solver: str = "qr",
    allow_rank_deficient: bool = False,
    refine: bool = False,
    exclude_outliers: bool = False,
) -> Identification:
    """Weighted least squares identification (as `trueaxis identify`); GIL released."""

class Candidates:
    """A campaign's records as candidates of an optimal (D, A, E, G) design."""
    def __init__(self, campaign: Campaign) -> None: ...
    def __len__(self) -> int: ...
    def check(self, count: int, starts: int) -> None: ...
    def exchange_starts(
        self, count: int, start: int, stop: int, *, criterion: str = "d", seed: int = 1
    ) -> List[Tuple[int, Optional[List[int]], Optional[float]]]:
        """Starts start..stop of the exchange algorithm (a chunk), each on its own random stream."""
    def best_of(
        self, count: int, outcomes: Sequence[Tuple[int, Optional[List[int]], Optional[float]]], *, criterion: str = "d"
    ) -> results.OptimalDesign:
        """Merge of chunks: the document of `trueaxis design optimal --json`."""
    def exchange(
        self, count: int, *, criterion: str = "d", starts: int = 5, seed: int = 1, progress: Optional[_Progress] = None
    ) -> results.OptimalDesign:
        """The document of `trueaxis design optimal --json`; progress(done, total) after each round of starts."""

class Sources:
    """Uncertainty sources and Monte Carlo settings (a sources TOML file)."""
    @staticmethod
    def from_file(path: _Path) -> Sources: ...
    @staticmethod
    def from_toml(text: str, origin: str = "<sources>") -> Sources: ...
    @staticmethod
    def from_dict(d: Mapping[str, Any]) -> Sources: ...
    @property
    def names(self) -> List[str]: ...
    @property
    def seed(self) -> int: ...

class UncertaintyPlan:
    """GUM and adaptive Monte Carlo (JCGM 101/102) budget of an identification, runnable in one
    process or as chunks on any engine (bit-identical for the same seed)."""
    @staticmethod
    def from_design(path: _Path, sources: Sources, *, seed: Optional[int] = None, budget: bool = True) -> UncertaintyPlan: ...
    @staticmethod
    def from_campaign(
        machine: Machine,
        campaign: Campaign,
        sources: Sources,
        *,
        point_time: float = 0.75,
        seed: Optional[int] = None,
        budget: bool = True,
    ) -> UncertaintyPlan: ...
    @property
    def stages(self) -> int: ...
    def stage_name(self, stage: int) -> Optional[str]: ...
    @property
    def parameters(self) -> List[str]: ...
    @property
    def seed(self) -> int: ...
    @property
    def trials_per_sequence(self) -> int: ...
    @property
    def max_sequences(self) -> int: ...
    def chunks(self, sequence: int, blocks_per_chunk: Optional[int] = None) -> List[_Chunk]: ...
    def run_chunk(self, stage: int, chunk: _Chunk) -> _Array:
        """(trials, parameters) trial values in the parameter units; GIL released."""
    def start(self) -> BudgetRun: ...
    def run(
        self,
        *,
        poses: Optional[_Array] = None,
        tool_point: Optional[_Point] = None,
        work_point: Optional[_Point] = None,
        frame: str = "workpiece",
        progress: Optional[_Progress] = None,
    ) -> results.UncertaintyBudget:
        """The document of `trueaxis uncertainty --json`, in this process; progress(done, total)
        after each Monte Carlo sequence (total: the most sequences of every stage)."""

class BudgetRun:
    """A budget being assembled from chunks, sequence by sequence, per stage."""
    def next_sequence(self, stage: int) -> Optional[int]: ...
    @property
    def done(self) -> bool: ...
    def push(self, stage: int, chunks: Sequence[Tuple[_Chunk, _Array]]) -> bool: ...
    def finish(
        self,
        *,
        poses: Optional[_Array] = None,
        tool_point: Optional[_Point] = None,
        work_point: Optional[_Point] = None,
        frame: str = "workpiece",
    ) -> results.UncertaintyBudget: ...

def fit(
    data: _Path,
    parameter: str,
    *,
    machine: Optional[Machine] = None,
    instrument: Optional[str] = None,
    optics_offset: Optional[Tuple[float, float]] = None,
    beam_on: Optional[str] = None,
    level_reference: str = "base",
    errors_in: Optional[Errors] = None,
    tool_point: Optional[_Point] = None,
    work_point: Optional[_Point] = None,
    at: Optional[Mapping[str, float]] = None,
    position: Optional[str] = None,
    value: str = "dev",
    domain: Optional[Tuple[float, float]] = None,
    family: str = "piecewise",
    degree: int = 2,
    knots: Optional[Sequence[float]] = None,
    knot_spacing: Optional[float] = None,
    continuity: int = 1,
    constant: bool = True,
    constraint: str = "none",
    periodic: Optional[Sequence[str]] = None,
    refine_wavelength: Optional[float] = None,
    stepwise: Optional[float] = None,
    direction: Optional[str] = None,
    drift: bool = False,
    scale_temperature: Union[float, str, None] = None,
    scale_expansion: Optional[float] = None,
    artefact_temperature: Union[float, str, None] = None,
    artefact_expansion: Optional[float] = None,
    temperature_datum: float = 0.0,
    no_file_temperature: bool = False,
    errors_out: Optional[_Path] = None,
) -> results.DirectFit:
    """The document of `trueaxis fit --json`: a parametric error function (piecewise polynomial,
    B-spline, Legendre, periodic terms) fitted to one motion error measured along its axis
    (positions in mm or deg, values in um or urad), with stepwise selection; the keyword arguments
    are the command's options (at: the other axes' positions, e.g. {"Z": -200}); errors_out writes
    or updates an error-values file (needs machine)."""

def iso230_2(
    path: _Path,
    *,
    scale_temperature: Optional[Union[float, str]] = None,
    scale_expansion: Optional[float] = None,
    artefact_temperature: Optional[Union[float, str]] = None,
    artefact_expansion: Optional[float] = None,
    temperature_datum: float = 0.0,
    no_file_temperature: bool = False,
) -> results.PositioningTest:
    """The document of `trueaxis iso230-2 --json` for a table or a Renishaw .rtl file (um, urad for a
    rotary axis; coverage factor 2): deviations corrected to 20 degC with the scale's and/or the
    artefact's temperature (degC, or a column name) and expansion coefficient (um/m/K) about
    temperature_datum (mm), else with the file's material temperature unless no_file_temperature.
    Warnings and notes are issued as TrueaxisWarning."""

def iso230_4(
    path: _Path,
    *,
    machine: Optional[Machine] = None,
    plane: Optional[str] = None,
    radius: Optional[float] = None,
    centre: Optional[_Point] = None,
    feed: Optional[float] = None,
    pitch: Optional[float] = None,
    spike_width: float = 3.0,
) -> results.CircularTest:
    """The document of `trueaxis ballbar iso230-4 --json`: G, F, H (um), diagnostics on the machine's
    model. plane xy|yz|zx, radius (mm, the bar length), centre (mm), feed (mm/min), pitch (mm),
    spike_width (deg); plane and radius default to the file's header."""

def ballbar_identify(
    machine: Machine,
    a1: _Path,
    a2: _Path,
    c1: _Path,
    c2: _Path,
    *,
    method: str = "extended-bar",
    outer_offset: Optional[float] = None,
    outer_positions: Optional[Tuple[float, float]] = None,
    inner_positions: Optional[Tuple[float, float]] = None,
    normal_length: float = 100.0,
    extended_length: float = 150.0,
    pivot_offset_a: Optional[Tuple[float, float]] = None,
    pivot_offset_c: Optional[Tuple[float, float]] = None,
    noise: float = 1.0,
) -> results.BallbarIdentification:
    """The document of `trueaxis ballbar identify --json`: the 8 PIGEs of the two rotary axes (um,
    urad) with their single-run standard uncertainty, repeatability over runs, compensation
    residual per step (um). method extended-bar | two-pivot (outer_offset, mm) | four-setup
    (outer_positions, inner_positions, mm); lengths and pivot offsets in mm; noise in um."""

def ballbar_sensitivity(
    machine: Machine,
    *,
    method: str = "extended-bar",
    outer_offset: Optional[float] = None,
    outer_positions: Optional[Tuple[float, float]] = None,
    inner_positions: Optional[Tuple[float, float]] = None,
    normal_length: float = 100.0,
    extended_length: float = 150.0,
    setup_u: float = 1.0,
    bar_u: float = 1.0,
    noise: float = 1.0,
) -> results.BallbarSensitivity:
    """The document of `trueaxis ballbar sensitivity --json`: each PIGE's change per um of each setup
    error (um/um, urad/um), per um of bar noise, and its combined standard uncertainty (um, urad)
    for setup_u, bar_u and noise (standard uncertainties in um)."""

def ballbar_simulate(
    machine: Machine,
    test: str,
    *,
    errors: Optional[Errors] = None,
    method: str = "extended-bar",
    outer_offset: Optional[float] = None,
    outer_positions: Optional[Tuple[float, float]] = None,
    inner_positions: Optional[Tuple[float, float]] = None,
    normal_length: float = 100.0,
    extended_length: float = 150.0,
    plane: str = "xy",
    radius: float = 100.0,
    centre: Optional[_Point] = None,
    dir: str = "both",
    step: float = 1.0,
    start: float = 0.0,
    noise: float = 0.0,
    seed: int = 1,
) -> str:
    """The CSV of `trueaxis ballbar simulate`: simulated bar readings (axis columns in mm and deg,
    angle in deg, dir, dL in um) of a step a1|a2|c1|c2 of the rotary-axis method (method and bars
    as in ballbar_identify) or of an ISO 230-4 circle (plane, radius and centre in mm, start deg,
    dir ccw|cw|both); step in deg, noise in um (standard deviation) drawn from seed."""

_Part = Union[float, Tuple[float, float, float]]

class BudgetProblem:
    """An error-budget problem (Zhu 2008 appendix B): machine, tolerances (um, urad), points (mm),
    frame and pose sets (mm, deg), as the options of `trueaxis budget analyse` and `allocate`."""

    def __init__(
        self,
        machine: Machine,
        *,
        budget: Optional[_Path] = None,
        linear_um: float = 5.0,
        angular_urad: float = 10.0,
        squareness_urad: float = 10.0,
        poses: Union[_Path, npt.ArrayLike, None] = None,
        parts: Optional[Sequence[_Part]] = None,
        grid: Optional[int] = None,
        part_nodes: int = 5,
        rotary: Optional[Mapping[str, float]] = None,
        tool_point: Optional[_Point] = None,
        work_point: Optional[_Point] = None,
        frame: str = "workpiece",
    ) -> None: ...
    @property
    def sets(self) -> List[str]: ...
    @property
    def poses(self) -> List[npt.NDArray[np.float64]]: ...
    @property
    def components(self) -> List[str]: ...
    def analyse(self, *, out: Optional[_Path] = None, sensitivity: Optional[_Path] = None) -> results.BudgetAnalysis:
        """The document of `trueaxis budget analyse --json`: stack-up per pose set (um), singular
        values and part sensitivities (mm), shares (%) of every axis, kind and component."""
    def rss_at(self, poses: npt.ArrayLike) -> _Array:
        """The root-sum-square 3D error (um) at each pose (poses, axes; mm and deg) with the rotary
        axes where the first pose set has them: the map of `budget analyse --plots`."""
    def allocate(
        self,
        *,
        target_um: Optional[float] = None,
        target_xyz: Optional[Tuple[float, float, float]] = None,
        stack: str = "rss",
        seed: int = 1,
        generations: int = 500,
        out: Optional[_Path] = None,
    ) -> results.BudgetAllocation:
        """The document of `trueaxis budget allocate --json`: cost-optimal tolerances (um, urad)
        for a target volumetric error in um."""

def budget_configurations(
    *,
    part: Optional[_Part] = None,
    tool_length: float = 100.0,
    linear_um: float = 5.0,
    angular_urad: float = 10.0,
    squareness_urad: float = 10.0,
    nodes: int = 3,
    tilt_deg: float = 30.0,
    progress: Optional[_Progress] = None,
) -> results.BudgetConfigurations:
    """The document of `trueaxis budget configurations --json`: the 288 five-axis configurations
    ranked by the RMS of the root-sum-square 3D error (um), travel in mm."""

def budget_miniaturisation(
    *,
    sizes: Optional[Sequence[float]] = None,
    linear_um: float = 1.0,
    angular_urad: float = 4.84813681109536,
    relative_accuracy: float = 0.0001,
    seed: int = 1,
) -> results.BudgetMiniaturisation:
    """The document of `trueaxis budget miniaturisation --json`: a three-axis machine scaled to cubic
    parts of `sizes` mm (default 10 to 300), equal errors in um and urad (default 1 arcsec); per
    size the sensitivities (mm), shares (%) and the allocation for a target of relative_accuracy
    times the size (um)."""

def thermal_fit(
    data: _Path,
    error: Optional[str] = None,
    *,
    model: str = "regression",
    rates: int = 2,
    validate: Optional[str] = None,
    time_constants: Optional[int] = None,
    until: Optional[float] = None,
    sensors: Optional[Sequence[str]] = None,
    select: Optional[str] = None,
    position: Optional[str] = None,
    degree: int = 0,
    no_intercept: bool = False,
    geometric_degree: Optional[int] = None,
    by_direction: bool = False,
    ranges: Optional[Sequence[float]] = None,
    train_runs: Optional[Sequence[str]] = None,
    out: Optional[_Path] = None,
    parameter: Optional[str] = None,
    terms_out: Optional[_Path] = None,
    machine: Optional[Machine] = None,
    skip_missing: bool = False,
    split_gaps: bool = False,
    robust: Optional[str] = None,
) -> results.ThermalFit:
    """The document of `trueaxis thermal fit --json` for a campaign CSV (t in s, T:<sensor> in degC,
    the error in um): model regression | state-space, residual statistics (um) of training and
    validation; geometric_degree: the geometric/thermal split; by_direction / ranges (mm or deg):
    the segmented G-T model; or, with time_constants, the eq. 3.17 time constants (min). out: the model file;
    terms_out (with parameter): the model as error terms (T - 20 degC). skip_missing, split_gaps,
    robust ("huber" | "tukey"): as the command's --skip-missing, --split-gaps, --robust
    (docs/screening.md); robust fits give coefficient uncertainties (um/degC) under `robust`."""

def thermal_predict(model: _Path, data: _Path) -> results.ThermalPrediction:
    """The document of `trueaxis thermal predict --json`: per row the prediction (um), the measured
    value and the residual when the error column is present; residual statistics per run (um)."""

def thermal_modes(
    model: _Path,
    *,
    count: int = 10,
    share: float = 0.9,
    method: str = "auto",
    progress: Optional[_Progress] = None,
) -> results.ThermalModes:
    """The document of `trueaxis thermal modes --json` for a model file: per mode (numbered from 1)
    tau_min, tau_s, weight, share, dominant; the dominant modes carry `share` of the weight.
    method: auto | dense | lanczos | lobpcg; progress(done, total) as the modes converge."""

def thermal_place(
    model: _Path,
    *,
    count: int = 20,
    share: float = 0.9,
    method: str = "modal",
    sensors: Optional[int] = None,
    reuse: float = 0.8,
    score: bool = False,
    expansion: float = 10.8,
) -> results.ThermalPlacement:
    """The document of `trueaxis thermal place --json`: sensors (node, position in m, modes served)
    for the dominant modes (method modal | efi | exhaustive | gauss), the rank and condition number
    of Phi_s; score: every method scored by the error (um) of its elongation model, expansion in
    um/m/K."""

def compensate(
    machine: Machine,
    errors: Errors,
    format: str,
    out: _Path,
    *,
    points: int = 41,
    grid: Tuple[int, int, int] = (9, 9, 9),
    reference: Optional[Mapping[str, float]] = None,
    limit_um: Optional[float] = None,
    limit_urad: Optional[float] = None,
    comp_type: int = 1,
    max_lattice_points: Optional[int] = None,
    max_table_points: Optional[int] = None,
    max_cec_tables: Optional[int] = None,
    hal_component: str = "trueaxis_comp",
    temperatures: Optional[Mapping[str, float]] = None,
    poses: Optional[_Path] = None,
    force: bool = False,
) -> results.Compensation:
    """Writes controller tables into `out` (format: linuxcnc, linuxcnc-hal, isg, heidenhain, siemens,
    fanuc, lattice, csv, json; all files or none; `out` must hold no other files); the summary of
    `trueaxis compensate --json`, with what the format leaves out and the error it leaves over the
    travel (um). reference: {"X": mm, ...}; temperatures: {"T:name": degC}; poses: a pose CSV
    corrected pose by pose in its state (dir:<axis>, T:<sensor>) into corrections.csv (um, urad)."""

def correct_nc(
    machine: Machine,
    errors: Errors,
    program: _Path,
    *,
    out: Optional[_Path] = None,
    tolerance_um: float = 1.0,
    decimals: Optional[int] = None,
    dialect: Optional[str] = None,
    limit_um: Optional[float] = None,
    limit_urad: Optional[float] = None,
    temperatures: Optional[Mapping[str, float]] = None,
    force: bool = False,
) -> results.NcCorrection:
    """Corrected NC program (RS274/NGC as LinuxCNC 2.9 runs it, or the Fanuc dialect; `dialect`
    detected when None); the summary of `trueaxis nc --json`."""
