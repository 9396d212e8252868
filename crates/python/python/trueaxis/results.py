"""Typed results of trueaxis: every evaluation returns an object of one style.

Each result holds the document of the command line's ``--json`` output for the same call (the same
builders in the library produce both) and gives it three ways:

- named fields as attributes (``test.A``, ``budget.covariance``): a list of numbers is a numpy
  array (float64, or int64 when every entry is an integer; a JSON ``null``, i.e. a number that is
  not finite, is NaN), a list of lists of numbers a 2-D array, an object a ``Record`` with the same
  rules; the classes add arrays gathered across a table (``budget.std_uncertainty``, one value per
  parameter in ``budget.names`` order) and matrices the document writes as nested objects;
- ``to_dict()``: the document itself, equal to the command line's ``--json`` (a deep copy);
- ``to_dataframe(table)``: one of the result's tables (``table_names`` lists them; the first is the
  default) as a pandas DataFrame, nested objects flattened into ``outer.inner`` columns. pandas is
  optional: without it ``to_dataframe`` raises an ImportError that says how to install it.

For code written against the dicts of earlier versions, ``result["key"]`` (and ``in``, ``keys()``,
``get``) give the plain JSON values, and a result compares equal to its document (``result ==
cli_dict``). Units are those of the document's keys (``_um``, ``_mm``, ``unit`` fields; um, urad,
mm, deg, degC, s as everywhere in trueaxis). Results pickle as their documents.
"""

from __future__ import annotations

import copy
from typing import Any, Dict, Iterator, List, Optional, Sequence

import numpy as np


def _is_number(v: Any) -> bool:
    return v is None or (isinstance(v, (int, float)) and not isinstance(v, bool))


def _numeric(values: list) -> Optional[np.ndarray]:
    """A numpy array of a non-empty list of numbers, or of a rectangular list of such lists; None
    for anything else. Integers stay int64; a None (JSON null) makes the array float64 with NaN."""
    if not values:
        return None
    if all(_is_number(v) for v in values):
        if any(v is None for v in values) or not all(isinstance(v, int) for v in values):
            return np.array([np.nan if v is None else v for v in values], dtype=np.float64)
        return np.array(values, dtype=np.int64)
    rows = [_numeric(v) if isinstance(v, list) else None for v in values]
    if all(r is not None and r.ndim == 1 for r in rows) and len({len(r) for r in rows}) == 1:
        return np.array(rows, dtype=np.float64 if any(r.dtype.kind == "f" for r in rows) else np.int64)
    return None


def typed(value: Any) -> Any:
    """A JSON value with the rules of attribute access: arrays for numbers, Records for objects."""
    if isinstance(value, dict):
        return Record(value)
    if isinstance(value, list):
        array = _numeric(value)
        return array if array is not None else [typed(v) for v in value]
    return value


def _pandas(what: str):
    try:
        import pandas
    except ImportError:
        raise ImportError(f"{what} needs pandas, which is not installed: pip install pandas") from None
    return pandas


def _flatten(row: dict, prefix: str = "") -> Dict[str, Any]:
    """One table row: nested objects as `outer.inner` columns, lists of numbers as numpy arrays."""
    out: Dict[str, Any] = {}
    for key, value in row.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(_flatten(value, f"{name}."))
        elif isinstance(value, list):
            array = _numeric(value)
            out[name] = array if array is not None else value
        else:
            out[name] = value
    return out


def rows_of(value: Any, key_name: str = "name") -> List[dict]:
    """The rows of a table: a list of objects as it is, an object of objects as rows whose first
    column `key_name` is the key."""
    if isinstance(value, dict):
        return [{key_name: k, **v} for k, v in value.items()]
    return list(value or [])


class Record:
    """A JSON object of a result: fields as attributes (numbers as numpy arrays, objects as
    Records), ``record["key"]`` the plain JSON value, ``to_dict()`` the object itself."""

    __slots__ = ("_doc",)

    def __init__(self, doc: Dict[str, Any]):
        if not isinstance(doc, dict):
            raise TypeError(f"{type(self).__name__}: expected a dict (a --json document), got a {type(doc).__name__}")
        object.__setattr__(self, "_doc", doc)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        try:
            return typed(self._doc[name])
        except KeyError:
            fields = ", ".join(k for k in self._doc if k.isidentifier())
            raise AttributeError(f"{type(self).__name__} has no field `{name}` (fields: {fields})") from None

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"{type(self).__name__} is read-only (to_dict() gives a copy to edit)")

    def __getitem__(self, key: str) -> Any:
        return self._doc[key]

    def __contains__(self, key: object) -> bool:
        return key in self._doc

    def __iter__(self) -> Iterator[str]:
        return iter(self._doc)

    def __len__(self) -> int:
        return len(self._doc)

    def keys(self):
        return self._doc.keys()

    def get(self, key: str, default: Any = None) -> Any:
        return self._doc.get(key, default)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Record):
            return self._doc == other._doc
        if isinstance(other, dict):
            return self._doc == other
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def __dir__(self) -> List[str]:
        return sorted(set(super().__dir__()) | {k for k in self._doc if k.isidentifier()})

    def __reduce__(self):
        return (type(self), (self._doc,))

    def __repr__(self) -> str:
        fields = [k for k in self._doc if k.isidentifier()]
        shown = ", ".join(fields[:8]) + (", ..." if len(fields) > 8 else "")
        return f"{type(self).__name__}({shown})"

    def to_dict(self) -> Dict[str, Any]:
        """The document (the command line's --json), as plain Python objects (a copy)."""
        return copy.deepcopy(self._doc)


class Result(Record):
    """A result: a Record with tables (``table_names``, ``to_dataframe``)."""

    __slots__ = ()
    #: table name -> (key of the document, name of the key column for an object of objects)
    _tables: Dict[str, tuple] = {}

    @property
    def table_names(self) -> List[str]:
        """Names of the tables ``to_dataframe`` gives (the first is the default)."""
        return list(self._tables)

    def _rows(self, table: str) -> List[dict]:
        key, key_name = self._tables[table]
        return rows_of(self._doc.get(key), key_name)

    def column(self, table: str, field: str) -> np.ndarray:
        """One field of every row of a table as a numpy array (NaN where null)."""
        if table not in self._tables:
            raise KeyError(f"{type(self).__name__} has no table `{table}` (tables: {', '.join(self._tables)})")
        values = [r.get(field) for r in self._rows(table)]
        array = _numeric(values)
        return array if array is not None else np.array(values, dtype=object)

    def to_dataframe(self, table: Optional[str] = None):
        """A table of the result as a pandas DataFrame (pandas is optional)."""
        if not self._tables:
            raise TypeError(f"{type(self).__name__} has no table")
        table = table or next(iter(self._tables))
        if table not in self._tables:
            raise KeyError(f"{type(self).__name__} has no table `{table}` (tables: {', '.join(self._tables)})")
        pd = _pandas(f"{type(self).__name__}.to_dataframe")
        return pd.DataFrame([_flatten(r) for r in self._rows(table)])


def _matrix(rows: Sequence[Sequence[Any]]) -> np.ndarray:
    """A float64 matrix of a list of rows (NaN where null)."""
    array = _numeric(list(rows))
    return np.zeros((0, 0)) if array is None else array.astype(np.float64)


class UncertaintyBudget(Result):
    """GUM and adaptive Monte Carlo uncertainty of identified parameters (JCGM 100/101/102; `trueaxis
    uncertainty --json`): per parameter (``names``, ``units``: um, urad or um/mm^k) the Monte Carlo
    estimate, standard uncertainty and coverage interval, the GUM's, the budget per source; the
    covariance matrices; the uncertainty of the predicted dx dy dz at the poses (um) if given."""

    __slots__ = ()
    _tables = {"parameters": ("parameters", "name"), "poses": ("poses", "name"), "history": ("history", "name")}

    def _rows(self, table: str) -> List[dict]:
        if table == "parameters":  # in the order of the arrays
            return [{"name": n, **self._doc["parameters"][n]} for n in self._doc["parameter_order"]]
        return super()._rows(table)

    def _per_parameter(self, *path: str) -> np.ndarray:
        """One field of every parameter, in ``names`` order (float64, NaN where null)."""
        out = []
        for name in self._doc["parameter_order"]:
            v = self._doc["parameters"][name]
            for p in path:
                v = v[p]
            out.append(v)
        array = _numeric(out)
        return np.zeros(0) if array is None else array.astype(np.float64)

    @property
    def names(self) -> List[str]:
        """Parameter names, the order of every array."""
        return list(self._doc["parameter_order"])

    @property
    def units(self) -> List[str]:
        return [self._doc["parameters"][n]["unit"] for n in self.names]

    @property
    def estimate(self) -> np.ndarray:
        """Monte Carlo estimates (parameter units)."""
        return self._per_parameter("estimate")

    @property
    def std_uncertainty(self) -> np.ndarray:
        """Monte Carlo standard uncertainties (parameter units)."""
        return self._per_parameter("std_uncertainty")

    @property
    def interval(self) -> np.ndarray:
        """Coverage intervals (low, high) of probability ``coverage``: shape (parameters, 2)."""
        return self._per_parameter("interval")

    @property
    def gum_std_uncertainty(self) -> np.ndarray:
        """Standard uncertainties by the law of propagation (GUM)."""
        return self._per_parameter("gum", "std_uncertainty")

    @property
    def covariance(self) -> np.ndarray:
        """Monte Carlo covariance (parameters x parameters, parameter units squared)."""
        return _matrix(self._doc["covariance"]["monte_carlo"])

    @property
    def gum_covariance(self) -> np.ndarray:
        """GUM covariance (parameters x parameters)."""
        return _matrix(self._doc["covariance"]["gum"])

    @property
    def sources(self) -> List[str]:
        """Sources of the budget (the columns of ``budget``); empty with a single source."""
        first = self._doc["parameters"][self.names[0]] if self.names else {}
        return list(first.get("gum_std_uncertainty_per_source", {}))

    @property
    def budget(self) -> np.ndarray:
        """GUM standard uncertainty of every parameter due to each source alone: (parameters,
        sources), parameter units."""
        sources = self.sources
        return _matrix([[self._doc["parameters"][n]["gum_std_uncertainty_per_source"][s] for s in sources] for n in self.names])


class OptimalDesign(Result):
    """An optimal measurement design (Soons 1993 §4.3; `trueaxis design optimal --json`): the chosen
    candidates (``chosen``, 0-based indices of the campaign's records) and the D, A, E, G criteria
    of the design and of all candidates."""

    __slots__ = ()


class PositioningTest(Result):
    """ISO 230-2:2014 accuracy and repeatability of positioning (`trueaxis iso230-2 --json`): A, R,
    E, M, B and their unidirectional values in ``unit`` (um, or urad for a rotary axis), coverage
    factor 2; per target position the means, standard deviations and reversal values (table
    ``positions``); ``targets`` in ``position_unit``."""

    __slots__ = ()
    _tables = {"positions": ("positions", "name")}


class CircularTest(Result):
    """ISO 230-4 circular test with a ballbar (`trueaxis ballbar iso230-4 --json`): per run (table
    ``runs``) the circular deviation G, radial deviation F, radius change and centre (um);
    hysteresis ``H_um``; the diagnostics fitted on the machine's model (table ``diagnostics``)."""

    __slots__ = ()
    _tables = {"runs": ("runs", "name"), "diagnostics": ("diagnostics", "name")}


class BallbarIdentification(Result):
    """The 8 PIGEs of two rotary axes from the four steps of Jiang 2014 (`trueaxis ballbar identify
    --json`): values and standard uncertainties (um, urad; table ``parameters``), the
    compensation residual per step, warnings."""

    __slots__ = ()
    _tables = {"parameters": ("parameters", "name"), "compensation_residual": ("compensation_residual", "name")}

    @property
    def names(self) -> List[str]:
        return list(self._doc["parameters"])

    @property
    def values(self) -> np.ndarray:
        """The identified PIGEs (um, urad) in ``names`` order."""
        return self.column("parameters", "value")

    @property
    def std_uncertainty(self) -> np.ndarray:
        """Standard uncertainty of a single run (um, urad) in ``names`` order."""
        return self.column("parameters", "std_uncertainty")


class BallbarSensitivity(Result):
    """The sensitivity of a rotary-axis ballbar method (`trueaxis ballbar sensitivity --json`): per
    PIGE (table ``parameters``) the combined standard uncertainty from the setup, the bar and the
    noise."""

    __slots__ = ()
    _tables = {"parameters": ("parameters", "name")}


class DirectFit(Result):
    """A parametric error function fitted to one error measured along its axis (Soons 1993 §3.2;
    `trueaxis fit --json`): the functions kept by stepwise selection (table ``terms``: function,
    coefficient, standard uncertainty), the residual statistics and the 95 % prediction band in
    ``unit`` (um or urad); with both directions fitted, the fits ``plus`` and ``minus``."""

    __slots__ = ()
    _tables = {"terms": ("terms", "name")}

    @property
    def coefficients(self) -> np.ndarray:
        """The coefficients of the functions kept (one direction), in ``unit`` per function value."""
        return self.column("terms", "coefficient")


class ThermalFit(Result):
    """A thermal error model fitted to a campaign (`trueaxis thermal fit --json`): the model and
    the residual statistics (um) of the training and of each validation part (table
    ``residuals``); or, with ``time_constants``, the shared time constants (``tau_min``) and the
    amplitudes per run and sensor (table ``amplitudes``)."""

    __slots__ = ()
    _tables = {"residuals": (None, "part"), "amplitudes": ("amplitudes", "name")}

    def _rows(self, table: str) -> List[dict]:
        if table == "residuals":
            parts = {"training": self._doc["training"]} if "training" in self._doc else {}
            parts.update(self._doc.get("validation") or {})
            return rows_of(parts, "part")
        return super()._rows(table)


class ThermalPrediction(Result):
    """A thermal error model evaluated on a campaign (`trueaxis thermal predict --json`): per row
    (table ``samples``) the run, ``t`` (s), the prediction and, with the error column present, the
    measured value and the residual (um); residual statistics per run (table ``residuals``)."""

    __slots__ = ()
    _tables = {"samples": ("samples", "name"), "residuals": ("residuals", "run")}

    @property
    def t(self) -> np.ndarray:
        """Times (s) of the rows."""
        return self.column("samples", "t")

    @property
    def predicted(self) -> np.ndarray:
        """Predicted error (um) of every row."""
        return self.column("samples", "predicted")


class ThermalPlacement(Result):
    """Temperature sensors placed for the dominant modes of a thermal model (Zhu 2008 §3.4;
    `trueaxis thermal place --json`): the sensors (table ``sensors``: node, position in m, the
    dominant modes each serves, numbered from 1), the rank and condition number of the sensor-mode
    matrix; with ``score=True`` every method scored by the error of its elongation model (table
    ``scores``, um)."""

    __slots__ = ()
    _tables = {"sensors": ("sensors", "name"), "scores": ("scores", "name")}

    @property
    def nodes(self) -> np.ndarray:
        """The sensor nodes."""
        return self.column("sensors", "node")


class ThermalModes(Result):
    """The thermal modes of a model (`trueaxis thermal modes --json`): per mode (table ``modes``)
    the time constant (``tau_min``, ``tau_s``), the weight under the model's step load, its share
    and whether it is dominant; ``dominant`` lists the dominant modes (numbered from 1)."""

    __slots__ = ()
    _tables = {"modes": ("modes", "mode")}

    @property
    def tau_s(self) -> np.ndarray:
        """Time constants (s), longest first."""
        return self.column("modes", "tau_s")

    @property
    def share(self) -> np.ndarray:
        """Each mode's share of the computed modes' total weight."""
        return self.column("modes", "share")


class Prediction(Result):
    """Predicted errors at the poses of a file (`trueaxis predict --json`): per pose (table
    ``poses``) the axis positions (mm, deg) and dx dy dz (um), drx dry drz (urad), dL (um)."""

    __slots__ = ()
    _tables = {"poses": ("poses", "name")}


class Compensation(Result):
    """Compensation files written for a controller (`trueaxis compensate --json`): the files, the
    error before and the error the files leave (um)."""

    __slots__ = ()


class NcCorrection(Result):
    """An NC program corrected for the predicted errors (`trueaxis nc --json`): the corrected
    program and its statistics."""

    __slots__ = ()


class BudgetAnalysis(Result):
    """The forward analysis of an error budget (Zhu 2008 appendix B; `trueaxis budget analyse
    --json`): per pose set (``sets``, one per part size) the root-sum-square and worst-case stack-up
    (um), singular values and part sensitivities (mm), and the shares (%) of every axis, kind and
    component. The tables hold the rows of every set, with its label in column ``set``."""

    __slots__ = ()
    _tables = {"components": ("components", "set"), "per_pose": ("per_pose", "set"), "by_axis": ("by_axis", "set"),
               "by_kind": ("by_kind", "set")}

    def _rows(self, table: str) -> List[dict]:
        key = self._tables[table][0]
        return [{"set": s["label"], **row} for s in self._doc["sets"] for row in s[key]]

    @property
    def rss_max(self) -> np.ndarray:
        """Largest root-sum-square 3D error (um) of each set."""
        return np.array([s["rss_um"]["max"] for s in self._doc["sets"]], dtype=np.float64)

    @property
    def worst_case_max(self) -> np.ndarray:
        """Largest worst-case 3D error (um) of each set."""
        return np.array([s["worst_case_um"]["max"] for s in self._doc["sets"]], dtype=np.float64)


class BudgetAllocation(Result):
    """Cost-optimal tolerances for a target volumetric error (Zhu 2008 eqs. B.5-B.8; `trueaxis
    budget allocate --json`): per component (table ``components``) the tolerance (um, urad), its
    homogenised value, lower limit and cost; the binding constraints (table ``active``)."""

    __slots__ = ()
    _tables = {"components": ("components", "name"), "active": ("active", "name")}

    @property
    def names(self) -> List[str]:
        return [c["name"] for c in self._doc["components"]]

    @property
    def tolerances(self) -> np.ndarray:
        """The allocated tolerances (um for linear, urad for angular and squareness errors)."""
        return self.column("components", "tolerance").astype(np.float64)


class BudgetConfigurations(Result):
    """The five-axis configuration study (Zhu 2008 appendix C; `trueaxis budget configurations
    --json`): the 288 configurations ranked by the RMS of their root-sum-square 3D error (table
    ``ranking``, um), the travel (mm) and space utility per category (table ``travel``)."""

    __slots__ = ()
    _tables = {"ranking": ("ranking", "name"), "travel": ("travel", "name")}


class BudgetMiniaturisation(Result):
    """The miniaturisation case of the error budget (Zhu 2008 appendix B.2; `trueaxis budget
    miniaturisation --json`): per part size (table ``sizes``, mm) the root-sum-square error (um),
    part sensitivities and robustness indices (mm), the shares by axis and kind (%) and the
    allocation for a constant relative accuracy (target in um)."""

    __slots__ = ()
    _tables = {"sizes": ("sizes", "name")}

    @property
    def size_mm(self) -> np.ndarray:
        """The part sizes (mm)."""
        return self.column("sizes", "size_mm")
