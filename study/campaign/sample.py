"""Sampled designs: the ``[sample]`` table, its distributions, and the ``sample`` axis.

A campaign may sample keys instead of (or beside) sweeping them::

    [sample]
    method = "saltelli"       # "lhs", "sobol", "saltelli" (Sobol' indices), "morris"
    count = 256               # points (lhs, sobol), base samples (saltelli), trajectories (morris)
    seed = 1
    "load.normal_force" = { distribution = "log-uniform", range = [100.0, 1000.0] }
    "friction.coefficient" = { distribution = "uniform", range = [0.1, 0.5] }
    "body2.nu" = { distribution = "normal", mean = 0.3, std = 0.02, bounds = [0.2, 0.4] }
    "grid.n" = { distribution = "discrete", values = [16, 32] }

The design is drawn in the unit hypercube (one column per key) by ``scipy.stats.qmc`` (Latin
hypercube, scrambled Sobol') or SALib (Saltelli's scheme on a Sobol' sequence, Morris
trajectories), and each column is mapped to its key's values by the distribution's quantile
function.  The rows become one zipped axis, the dimension ``sample``, whose coordinates are the
sampled keys; ``[sweep]`` and ``[zip]`` axes combine with it as a product (a design per value
of a swept key).  The unit design is kept with the campaign (the analysis of Morris' elementary
effects needs it, :mod:`study.analysis.global_sensitivity`).

Rows of a design may repeat (a discrete key): those are one case, computed once, stored in
every row that names it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .naming import CampaignError, _kind

#: Sampling methods: name -> what it is for.
METHODS = {
    "lhs": "Latin hypercube (scipy.stats.qmc): space filling, any count",
    "sobol": "scrambled Sobol' sequence (scipy.stats.qmc): space filling, a power of 2",
    "saltelli": "Saltelli's scheme (SALib) for Sobol' indices: count N (a power of 2) gives "
    "N (D + 2) cases, N (2 D + 2) with second_order",
    "morris": "Morris trajectories (SALib) for elementary effects: count r gives r (D + 1) cases",
}
#: Distributions of a sampled key: name -> the fields it takes.
DISTRIBUTIONS = {
    "uniform": ("range",),
    "log-uniform": ("range",),
    "normal": ("mean", "std", "bounds"),
    "discrete": ("values",),
}
#: Settings of ``[sample]`` beside the keys.
SETTINGS = ("method", "count", "seed", "second_order", "levels")
#: The sampled dimension's name.
SAMPLE_DIM = "sample"
#: Most rows a design may have.
MAX_ROWS = 10_000_000


@dataclass(frozen=True)
class Distribution:
    """How a sampled key's values spread: a quantile function of the unit interval.

    Attributes
    ----------
    kind : str
        One of :data:`DISTRIBUTIONS`.
    low, high : float
        The range (uniform, log-uniform) or the truncation bounds (normal; infinite: none).
    mean, std : float
        Of the normal distribution (before truncation).
    values : tuple
        The discrete values (equally likely).
    """

    kind: str
    low: float = -math.inf
    high: float = math.inf
    mean: float = 0.0
    std: float = 0.0
    values: tuple = ()

    def quantile(self, u: np.ndarray) -> list:
        """The values at the unit-interval points ``u`` (Python numbers, or the discrete ones)."""
        u = np.asarray(u, dtype=float)
        if self.kind == "discrete":
            index = np.minimum((u * len(self.values)).astype(int), len(self.values) - 1)
            return [self.values[i] for i in index]
        if self.kind == "uniform":
            x = self.low + u * (self.high - self.low)
        elif self.kind == "log-uniform":
            x = self.low * (self.high / self.low) ** u
        else:
            from scipy.stats import truncnorm

            a, b = (self.low - self.mean) / self.std, (self.high - self.mean) / self.std
            x = truncnorm.ppf(u, a, b, loc=self.mean, scale=self.std)
        return [float(v) for v in x]

    @property
    def bounded(self) -> bool:
        """True when the values at u = 0 and 1 are finite (Morris' trajectories reach them)."""
        return self.kind != "normal" or (math.isfinite(self.low) and math.isfinite(self.high))

    def describe(self) -> str:
        """One line: ``log-uniform [100, 1000]``, ``normal 0.3 +- 0.02 in [0.2, 0.4]``..."""
        if self.kind == "discrete":
            return "discrete " + ", ".join(str(v) for v in self.values)
        if self.kind == "normal":
            cut = f" in [{self.low:g}, {self.high:g}]" if math.isfinite(self.low) else ""
            return f"normal {self.mean:g} +- {self.std:g}{cut}"
        return f"{self.kind} [{self.low:g}, {self.high:g}]"

    def to_dict(self) -> dict:
        """JSON-able form (infinite bounds as None)."""
        out: dict[str, Any] = {"distribution": self.kind}
        if self.kind == "discrete":
            out["values"] = list(self.values)
        elif self.kind == "normal":
            out.update(mean=self.mean, std=self.std)
            if math.isfinite(self.low):
                out["bounds"] = [self.low, self.high]
        else:
            out["range"] = [self.low, self.high]
        return out


@dataclass(frozen=True)
class Design:
    """A sampled design: method, settings, the keys' distributions and the unit-cube rows.

    Attributes
    ----------
    method : str
        One of :data:`METHODS`.
    count : int
        As given (points, base samples or trajectories).
    seed : int
        The generator's seed.
    second_order : bool
        Saltelli's design with the second-order rows.
    levels : int
        Morris' grid levels.
    keys : tuple of str
        The sampled (normalised) keys, one column each.
    distributions : tuple of Distribution
        One per key.
    unit : tuple of tuple of float
        The rows in the unit hypercube (``rows x len(keys)``).
    """

    method: str
    count: int
    seed: int
    second_order: bool
    levels: int
    keys: tuple[str, ...]
    distributions: tuple[Distribution, ...]
    unit: tuple[tuple[float, ...], ...]

    @property
    def rows(self) -> int:
        """Points of the design (the ``sample`` dimension's size)."""
        return len(self.unit)

    @property
    def block(self) -> int:
        """Rows that belong together: 1, or D + 2 (Saltelli), 2 D + 2 (second order), D + 1.

        A Saltelli block, a Morris trajectory; 1 for a space-filling design.
        """
        d = len(self.keys)
        return {"saltelli": 2 * d + 2 if self.second_order else d + 2, "morris": d + 1}.get(
            self.method, 1
        )

    def values(self) -> list[list]:
        """Each key's values down the design (one list per key)."""
        unit = np.asarray(self.unit, dtype=float).reshape(self.rows, len(self.keys))
        return [dist.quantile(unit[:, j]) for j, dist in enumerate(self.distributions)]

    def to_dict(self) -> dict:
        """JSON-able form (what ``campaign.json`` keeps)."""
        return {
            "method": self.method,
            "count": self.count,
            "seed": self.seed,
            "second_order": self.second_order,
            "levels": self.levels,
            "keys": list(self.keys),
            "distributions": [d.to_dict() for d in self.distributions],
            "unit": [list(row) for row in self.unit],
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> Design:
        """Rebuild from :meth:`to_dict` (no re-validation)."""
        return cls(
            data["method"], data["count"], data["seed"], data["second_order"], data["levels"],
            tuple(data["keys"]),
            tuple(_distribution(d, "") for d in data["distributions"]),
            tuple(tuple(row) for row in data["unit"]),
        )  # fmt: skip


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise CampaignError(f"{where}: must be a finite number, got {value!r}")
    return float(value)


def _pair(value: Any, where: str) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2:
        raise CampaignError(f"{where}: must be [low, high], got {value!r}")
    low, high = (_number(v, where) for v in value)
    if not low < high:
        raise CampaignError(f"{where}: low must be below high, got {value!r}")
    return low, high


def _distribution(spec: Any, where: str) -> Distribution:
    """A key's distribution from its inline table (messages name ``where``)."""
    if not isinstance(spec, Mapping) or "distribution" not in spec:
        raise CampaignError(
            f"{where}: must be a table with a distribution, e.g. "
            '{ distribution = "uniform", range = [0.1, 0.5] }'
        )
    kind = spec["distribution"]
    if kind not in DISTRIBUTIONS:
        raise CampaignError(
            f"{where}.distribution: must be one of {', '.join(DISTRIBUTIONS)}, got {kind!r}"
        )
    allowed = DISTRIBUTIONS[kind]
    unknown = sorted(set(spec) - {"distribution", *allowed})
    if unknown:
        raise CampaignError(
            f"{where}.{unknown[0]}: not a field of a {kind} distribution; it takes "
            f"{', '.join(allowed)}"
        )
    missing = [f for f in allowed if f not in spec and f != "bounds"]
    if missing:
        raise CampaignError(f"{where}: a {kind} distribution needs {missing[0]}")
    if kind == "discrete":
        values = spec["values"]
        if not isinstance(values, list) or not values:
            raise CampaignError(f"{where}.values: must be a non-empty list, got {values!r}")
        if any(isinstance(v, list | dict) for v in values):
            raise CampaignError(f"{where}.values: must be numbers, strings or booleans")
        if len({_kind(v) for v in values}) > 1:
            raise CampaignError(f"{where}.values: mixed value types {values!r}; use one type")
        if any(isinstance(v, float) and not math.isfinite(v) for v in values):
            raise CampaignError(f"{where}.values: must be finite, got {values!r}")
        if len({(type(v) is bool, v) for v in values}) != len(values):
            raise CampaignError(f"{where}.values: a value appears twice; give each once")
        return Distribution(kind, values=tuple(values))
    if kind == "normal":
        mean, std = _number(spec["mean"], f"{where}.mean"), _number(spec["std"], f"{where}.std")
        if std <= 0:
            raise CampaignError(f"{where}.std: must be positive, got {spec['std']!r}")
        low, high = -math.inf, math.inf
        if spec.get("bounds") is not None:
            low, high = _pair(spec["bounds"], f"{where}.bounds")
            if not low < mean < high:
                raise CampaignError(f"{where}.bounds: must hold the mean {mean:g}")
        return Distribution(kind, low, high, mean, std)
    low, high = _pair(spec["range"], f"{where}.range")
    if kind == "log-uniform" and low <= 0:
        raise CampaignError(f"{where}.range: a log-uniform range must be positive, got {low:g}")
    if not math.isfinite(high / low if kind == "log-uniform" else high - low):
        raise CampaignError(f"{where}.range: [{low:g}, {high:g}] overflows; narrow it")
    return Distribution(kind, low, high)


def _entries(raw: Mapping, prefix: str = ""):
    """``(dotted key, its table)`` of ``[sample]``: TOML splits unquoted dotted keys."""
    for key, value in raw.items():
        name = f"{prefix}{key}"
        if not prefix and key in SETTINGS:
            continue
        if isinstance(value, Mapping) and "distribution" not in value:
            yield from _entries(value, name + ".")
        else:
            yield name, value


def parse_sample(raw: Any, normalise) -> Design:
    """The :class:`Design` of a ``[sample]`` table, drawn.

    Parameters
    ----------
    raw : mapping
        The parsed table.
    normalise : callable
        ``normalise(written, where)``: the normalised dotted key (raises on a bad one).

    Raises
    ------
    CampaignError
        Naming the setting or key and what to change.
    """
    if not isinstance(raw, Mapping):
        raise CampaignError("[sample]: must be a table (method, count, seed and the keys)")
    method = raw.get("method")
    if method not in METHODS:
        raise CampaignError(
            f"sample.method: must be one of {', '.join(METHODS)}, got {method!r} ("
            + "; ".join(f"{k}: {v}" for k, v in METHODS.items())
            + ")"
        )
    count = raw.get("count")
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise CampaignError(f"sample.count: must be a positive integer, got {count!r}")
    seed = raw.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise CampaignError(f"sample.seed: must be an integer >= 0, got {seed!r}")
    second_order = raw.get("second_order", False)
    if not isinstance(second_order, bool):
        raise CampaignError(f"sample.second_order: must be true or false, got {second_order!r}")
    if second_order and method != "saltelli":
        raise CampaignError("sample.second_order: only Saltelli's design has second-order rows")
    levels = raw.get("levels", 4)
    if isinstance(levels, bool) or not isinstance(levels, int) or levels < 2 or levels % 2:
        raise CampaignError(f"sample.levels: must be an even integer >= 2, got {levels!r}")
    if "levels" in raw and method != "morris":
        raise CampaignError("sample.levels: only Morris' trajectories have levels")
    keys, distributions, seen = [], [], {}
    for written, spec in _entries(raw):
        key = normalise(written, "[sample]")
        if key in seen:
            raise CampaignError(f'[sample] "{written}": {key} is sampled twice')
        seen[key] = written
        where = f'sample."{written}"'
        distribution = _distribution(spec, where)
        if method == "morris" and not distribution.bounded:
            raise CampaignError(
                f"{where}: Morris' trajectories reach the ends of the unit interval, where a "
                "normal distribution is infinite; give it bounds = [low, high]"
            )
        keys.append(key)
        distributions.append(distribution)
    if not keys:
        raise CampaignError(
            '[sample]: no key to sample; add e.g. "friction.coefficient" = '
            '{ distribution = "uniform", range = [0.1, 0.5] }'
        )
    if method in ("saltelli", "morris") and len(keys) < 2:
        raise CampaignError(f"[sample]: {method} needs two sampled keys or more (one is given)")
    if method in ("sobol", "saltelli") and count & (count - 1):
        low = 1 << (count.bit_length() - 1)
        raise CampaignError(
            f"sample.count: a Sobol' sequence keeps its balance at a power of 2; {count} is "
            f"not one (take {low} or {2 * low})"
        )
    d = len(keys)
    rows = {
        "saltelli": count * (2 * d + 2 if second_order else d + 2),
        "morris": count * (d + 1),
    }.get(method, count)
    if rows > MAX_ROWS:
        raise CampaignError(f"sample.count: {rows} rows; at most {MAX_ROWS} are drawn")
    unit = _draw(method, d, count, seed, second_order, levels)
    return Design(
        method, count, seed, second_order, levels, tuple(keys), tuple(distributions),
        tuple(tuple(float(v) for v in row) for row in unit),
    )  # fmt: skip


def salib_problem(names: list[str]) -> dict:
    """SALib's problem of a design's unit cube (one variable per name)."""
    return {"num_vars": len(names), "names": list(names), "bounds": [[0.0, 1.0]] * len(names)}


def _draw(method: str, d: int, count: int, seed: int, second_order: bool, levels: int):
    """The design's rows in the unit hypercube."""
    if method in ("lhs", "sobol"):
        from scipy.stats import qmc

        engine = qmc.LatinHypercube(d=d, rng=seed) if method == "lhs" else qmc.Sobol(d, rng=seed)
        return engine.random(count)
    problem = salib_problem([f"x{j}" for j in range(d)])
    if method == "saltelli":
        from SALib.sample import sobol

        return sobol.sample(problem, count, calc_second_order=second_order, seed=seed)
    from SALib.sample import morris

    return morris.sample(problem, count, num_levels=levels, seed=seed)
