"""trueaxis: find, explain and remove the quasi-static errors of multi-axis machine tools.

Python bindings of the Rust library (docs/python.md). Units as everywhere in trueaxis: axis
positions in mm (linear) and deg (rotary); errors in um (translations) and urad (rotations);
temperatures in degC; time in s. Results are numpy arrays, or dicts with the keys of the
command line's ``--json`` documents. Errors raise ``TrueaxisError``: ``InputError`` for bad input
(the command line's exit status 2), ``ComputationError`` for a failed computation (exit 1),
``ResourceError`` for the environment (a full disk, a permission, memory: exit 3). What
the command line prints on stderr as warnings or notes is issued as ``TrueaxisWarning``.
"""

from ._native import (
    BLOCK,
    PREDICTION_COLUMNS,
    PREDICTION_COLUMNS_WITH_DL,
    PREDICTION_UNITS,
    PREDICTION_UNITS_WITH_DL,
    BudgetRun,
    Campaign,
    Candidates,
    ComputationError,
    Errors,
    Identification,
    InputError,
    Machine,
    ResourceError,
    Sources,
    TrueaxisError,
    TrueaxisWarning,
    UncertaintyPlan,
    __version__,
    ballbar_identify,
    ballbar_sensitivity,
    compensate,
    correct_nc,
    identify,
    iso230_2,
    iso230_4,
    thermal_fit,
    thermal_predict,
)

__all__ = [
    "BLOCK",
    "PREDICTION_COLUMNS",
    "PREDICTION_COLUMNS_WITH_DL",
    "PREDICTION_UNITS",
    "PREDICTION_UNITS_WITH_DL",
    "BudgetRun",
    "Campaign",
    "Candidates",
    "ComputationError",
    "Errors",
    "Identification",
    "InputError",
    "Machine",
    "ResourceError",
    "Sources",
    "TrueaxisError",
    "TrueaxisWarning",
    "UncertaintyPlan",
    "__version__",
    "ballbar_identify",
    "ballbar_sensitivity",
    "compensate",
    "correct_nc",
    "identify",
    "iso230_2",
    "iso230_4",
    "thermal_fit",
    "thermal_predict",
]
