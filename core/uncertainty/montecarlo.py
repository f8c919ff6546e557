"""Propagation of distributions by Monte Carlo (JCGM 101:2008, GUM Supplement 1).

Each input quantity X_i is drawn from its probability distribution (JCGM 101 clause 6.4), the
draws are propagated through the measurement model Y = f(X) (clause 7.5), and from the model
values come the estimate y, its standard uncertainty u(y) (clause 7.6, eqs. (12), (13)) and a
coverage interval (clause 7.7).  The number of trials is chosen adaptively (clause 7.9): batches
of M = 10⁴ trials are added until twice the standard deviation of the batch means of y, u(y) and
the interval's endpoints is at most the numerical tolerance δ of u(y) (clause 7.9.2).  Clause 8
then validates the GUM interval y ± U_p: it is validated when both endpoint differences d_low,
d_high are at most δ (clause 8.2, eqs. (27), (28)).

Every draw is vectorised numpy; a generator (``numpy.random.Generator``) is passed in, so a
fixed seed reproduces a run.  :func:`metro.core.uncertainty.montecarlo_examples.jcgm101_examples`
reproduces the worked examples of clause 9 with these functions.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

import attrs
import numpy as np

from .budget import DIVISORS

#: the distributions a :class:`Input` can have (``"uniform"`` is ``"rectangular"``)
DISTRIBUTIONS = ("normal", "rectangular", "uniform", "triangular", "arcsine", "t", "ctrap")

#: trials per batch of the adaptive procedure (JCGM 101 clause 7.9.4 b: max(J/(1 − p), 10⁴))
BATCH = 10_000

#: the fewest batches the adaptive procedure runs: the standard deviation s of h batch means
#: rests on h − 1 degrees of freedom, and with h = 2 (clause 7.9.4's minimum) a lucky pair stops
#: the run at 2·10⁴ trials with endpoints off by several δ; ten batches give s nine
MIN_BATCHES = 10

#: the largest number of trials the adaptive procedure runs before it stops unconverged
MAX_TRIALS = 5_000_000


@attrs.frozen
class Input:
    """One input quantity X_i and its distribution, given by its expectation ``x`` and its
    standard uncertainty ``u`` (JCGM 101 Table 1):

    * ``"normal"`` N(x, u²) (clause 6.4.7);
    * ``"rectangular"``/``"uniform"`` R(x − a, x + a), a = √3·u (clause 6.4.2);
    * ``"triangular"`` T(x − a, x + a), a = √6·u (clause 6.4.4);
    * ``"arcsine"`` (U-shaped) U(x − a, x + a), a = √2·u (clause 6.4.6);
    * ``"t"`` the scaled and shifted t_ν(x, u²), x + u·t_ν (clause 6.4.9.7): its standard
      deviation is u·√(ν/(ν − 2));
    * ``"ctrap"`` the rectangular distribution with inexactly known limits, half-width ``u`` is
      then read as a and ``d`` as the half-width of the limits' uncertainty (clause 6.4.3).

    >>> Input("rectangular", 1.0, 0.5).half_width
    0.8660254037844386
    """

    distribution: str = attrs.field(validator=attrs.validators.in_(DISTRIBUTIONS))
    x: float = attrs.field(converter=float)
    u: float = attrs.field(converter=float)
    #: the degrees of freedom ν of a ``"t"`` input
    dof: float = attrs.field(default=math.inf, converter=float)
    #: the half-width d of the limits' uncertainty of a ``"ctrap"`` input
    d: float = attrs.field(default=0.0, converter=float)

    @property
    def half_width(self) -> float:
        """The half-width a of a bounded distribution (``u`` itself for ``"ctrap"``)."""
        factor = 1.0 if self.distribution == "ctrap" else DIVISORS.get(self.distribution)
        return self.u * (factor or math.nan)

    def draw(self, size: int, rng: np.random.Generator) -> np.ndarray:
        """``size`` values of X_i (JCGM 101 clause 6.4, Table 1 and clauses 6.4.2.4, 6.4.3.4,
        6.4.4.4, 6.4.6.4, 6.4.7.4, 6.4.9.5).

        >>> v = Input("arcsine", 0.0, 1.0).draw(100_000, np.random.default_rng(1))
        >>> round(float(v.std()), 2), float(abs(v).max()) <= math.sqrt(2)
        (1.0, True)
        """
        dist, x, a = self.distribution, self.x, self.half_width
        if dist == "normal":
            return x + self.u * rng.standard_normal(size)
        if dist == "t":
            if math.isinf(self.dof):
                return x + self.u * rng.standard_normal(size)
            return x + self.u * rng.standard_t(self.dof, size)
        if dist in ("rectangular", "uniform"):
            return rng.uniform(x - a, x + a, size)
        if dist == "triangular":  # clause 6.4.4.4: x + a(r1 + r2 − 1)
            return x + a * (rng.random(size) + rng.random(size) - 1.0)
        if dist == "arcsine":  # clause 6.4.6.4: x + a·sin(2πr)
            return x + a * np.sin(2.0 * np.pi * rng.random(size))
        # ctrap, clause 6.4.3.4: a_s = (a − d) + 2d·r1, X = (x − a_s) + 2a_s·r2
        half = (a - self.d) + 2.0 * self.d * rng.random(size)
        return x + half * (2.0 * rng.random(size) - 1.0)


def linear_model(sensitivities: Sequence[float]) -> Callable[[np.ndarray], np.ndarray]:
    """The linear model Y = Σ c_i·X_i of a budget (JJF 1059.1 eq. (24)'s model) as a function of
    the draws ``x`` (shape n_inputs × M).

    >>> linear_model([1.0, -2.0])(np.array([[1.0], [1.0]]))
    array([-1.])
    """
    c = np.asarray(sensitivities, dtype=float)
    return lambda x: c @ x


@attrs.frozen
class MonteCarloResult:
    """What the Monte Carlo method gives (JCGM 101 clause 7.6, 7.7, 7.9)."""

    #: the estimate y, the mean of the model values (eq. (12))
    y: float
    #: its standard uncertainty u(y) (eq. (13))
    u: float
    #: the coverage probability p of the intervals
    p: float
    #: the shortest coverage interval (clause 7.7.2)
    shortest: tuple[float, float]
    #: the probabilistically symmetric coverage interval (clause 7.7.1)
    symmetric: tuple[float, float]
    #: the number of trials M·h
    trials: int
    #: the numerical tolerance δ of u(y) (clause 7.9.2)
    delta: float
    #: True when the adaptive procedure met its tolerance (clause 7.9.4 i) before MAX_TRIALS
    converged: bool


def numerical_tolerance(u: float, digits: int = 2) -> float:
    """δ = ½·10^l where u = c·10^l with c an integer of ``digits`` digits (JCGM 101 clause
    7.9.2).

    >>> numerical_tolerance(0.0754, 3), numerical_tolerance(36.0, 2)
    (5e-05, 0.5)
    >>> numerical_tolerance(2.0, 3)
    0.005
    """
    if not (u > 0 and math.isfinite(u)):
        raise ValueError(f"the numerical tolerance needs a finite u > 0, got {u}")
    exponent = math.floor(math.log10(u)) - (digits - 1)
    if round(u / 10.0**exponent) >= 10**digits:  # 9.96 with 2 digits is 10 = c·10^l, c = 10
        exponent += 1
    return float(0.5 * 10.0**exponent)


def coverage_intervals(
    values: np.ndarray, p: float = 0.95, *, presorted: bool = False, tolerance: float = 0.0
) -> tuple[tuple[float, float], tuple[float, float]]:
    """The shortest (clause 7.7.2) and the probabilistically symmetric (clause 7.7.1) 100p %
    coverage intervals of the model values: with the M values sorted, q = pM (an integer) or
    int(pM + ½); the symmetric one is [y_(r), y_(r+q)] with r = (M − q)/2 (or int((M − q + 1)/2)),
    the shortest the [y_(r*), y_(r*+q)] with the least length over r = 1, …, M − q.

    Where the symmetric interval is no longer than the shortest by more than ``tolerance`` (the
    numerical tolerance δ), it is taken as the shortest: near a symmetric output the length of
    [y_(r), y_(r+q)] is flat in r (it grows with the square of the shift), so the r* of a
    finite sample wanders by far more than δ while the two lengths agree within δ
    (docs/interpretations.md, "Monte Carlo: the shortest interval of a symmetric output").

    >>> coverage_intervals(np.arange(1.0, 101.0) ** 2, 0.9)
    ((1.0, 8281.0), (25.0, 9025.0))
    """
    y = values if presorted else np.sort(values)
    m = y.size
    q = int(p * m) if float(p * m).is_integer() else int(p * m + 0.5)
    if not 0 < q < m:
        raise ValueError(f"{m} values are too few for a {p:.2%} coverage interval")
    r = (m - q) // 2 if (m - q) % 2 == 0 else (m - q + 1) // 2
    r = max(r, 1)
    symmetric = (float(y[r - 1]), float(y[r + q - 1]))
    lengths = y[q:] - y[: m - q]
    best = int(np.argmin(lengths))
    if lengths[r - 1] - lengths[best] <= tolerance:
        return symmetric, symmetric
    return (float(y[best]), float(y[best + q])), symmetric


def _batch_figures(values: np.ndarray, p: float, digits: int) -> np.ndarray:
    u = float(values.std(ddof=1))
    delta = numerical_tolerance(u, digits) if u > 0 else 0.0
    shortest, _ = coverage_intervals(values, p, tolerance=delta)
    return np.array([values.mean(), u, shortest[0], shortest[1]])


def propagate(
    inputs: Sequence[Input],
    model: Callable[[np.ndarray], np.ndarray] | None = None,
    *,
    p: float = 0.95,
    digits: int = 2,
    rng: np.random.Generator | int | None = None,
    trials: int | None = None,
    max_trials: int = MAX_TRIALS,
    delta: float | None = None,
) -> MonteCarloResult:
    """Propagate the ``inputs`` through ``model`` (default: their sum) by Monte Carlo.

    ``model`` maps the draws, an array of shape (n_inputs, M), to the M model values (clause
    7.5).  With ``trials`` the method runs that many trials at once (clause 7.2); without, the
    adaptive procedure of clause 7.9.4 adds batches of :data:`BATCH` trials (at least
    :data:`MIN_BATCHES`) until 2·s ≤ δ for the
    means of y, u(y) and both endpoints of the shortest interval, δ from ``digits`` significant
    digits of u(y) (clause 7.9.2), or until ``max_trials``.  A given ``delta`` is used instead
    (clause 8.2 b: the tolerance of the GUM u(y) a validation compares with).

    A t input with ν ≤ 2 has no variance (clause 6.4.9.4): u(y) is then NaN and left out of the
    stopping rule, as it is with ν ≤ 4 (the sample variance of such draws has no variance, its
    batch values do not settle); y and the interval's endpoints still decide.

    JCGM 101 9.2.2, four N(0, 1) inputs, Y = X₁ + X₂ + X₃ + X₄:

    >>> r = propagate([Input("normal", 0, 1)] * 4, rng=1)
    >>> round(r.u, 1), round(r.shortest[1], 1)
    (2.0, 3.9)
    """
    rng = np.random.default_rng(rng)
    model = model or (lambda x: x.sum(axis=0))

    def run(m: int) -> np.ndarray:
        draws = np.empty((len(inputs), m))
        for i, x in enumerate(inputs):
            draws[i] = x.draw(m, rng)
        return np.asarray(model(draws), dtype=float).reshape(m)

    smallest_dof = min([i.dof for i in inputs if i.distribution == "t"], default=math.inf)
    watch = [0, 1, 2, 3] if smallest_dof > 4 else [0, 2, 3]

    def finish(values: np.ndarray, converged: bool) -> MonteCarloResult:
        r = summarise(values, p, digits, converged=converged, delta=delta)
        return r if smallest_dof > 2 else attrs.evolve(r, u=math.nan)

    if trials is not None:
        return finish(run(int(trials)), True)
    batches: list[np.ndarray] = []
    figures: list[np.ndarray] = []
    moments = np.zeros(2)  # Σ(v − y₁), Σ(v − y₁)² about the first batch's mean y₁
    while True:
        batches.append(run(BATCH))
        figures.append(_batch_figures(batches[-1], p, digits))
        centred = batches[-1] - figures[0][0]
        moments += (centred.sum(), centred @ centred)
        h = len(batches)
        if h < MIN_BATCHES:
            continue
        s = np.std(np.array(figures), axis=0, ddof=1) / math.sqrt(h)  # clause 7.9.4 f
        n = h * BATCH  # clause 7.9.4 g: u(y) from all h·M values
        u = math.sqrt(max(moments[1] - moments[0] ** 2 / n, 0.0) / (n - 1))
        tol = delta if delta is not None else numerical_tolerance(u, digits) if u > 0 else 0.0
        if u == 0 or bool(np.all(2.0 * s[watch] <= tol)):
            return finish(np.concatenate(batches), True)
        if h * BATCH >= max_trials:
            return finish(np.concatenate(batches), False)


def summarise(values: np.ndarray, p: float, digits: int = 2, *, converged: bool = True,
              delta: float | None = None) -> MonteCarloResult:
    """y, u(y) (JCGM 101 eqs. (12), (13)), both 100p % intervals (clause 7.7) and δ (clause
    7.9.2, or the given ``delta``) of the model values.

    >>> summarise(np.arange(1.0, 101.0) ** 2, 0.9).shortest
    (1.0, 8281.0)
    """
    y = np.sort(values)
    u = float(np.std(y, ddof=1))
    if delta is None:
        delta = numerical_tolerance(u, digits) if u > 0 else 0.0
    shortest, symmetric = coverage_intervals(y, p, presorted=True, tolerance=delta)
    return MonteCarloResult(
        float(np.mean(y)), u, float(p), shortest, symmetric, int(y.size), delta, converged
    )


@attrs.frozen
class Validation:
    """The comparison of the GUM interval y ± U_p with the Monte Carlo one (JCGM 101 clause 8)."""

    #: d_low = |y − U_p − y_low| (eq. (27))
    d_low: float
    #: d_high = |y + U_p − y_high| (eq. (28))
    d_high: float
    #: the numerical tolerance δ (clause 8.2 b, from u(y) as in clause 7.9.2)
    delta: float

    @property
    def validated(self) -> bool:
        """True when both d_low and d_high are at most δ (clause 8.2 c)."""
        return self.d_low <= self.delta and self.d_high <= self.delta


def validate_gum(
    y: float, expanded: float, interval: tuple[float, float], delta: float
) -> Validation:
    """Clause 8.2: d_low = |y − U_p − y_low|, d_high = |y + U_p − y_high| (eqs. (27), (28)); the
    GUM interval is validated when both are at most δ.

    JCGM 101 9.4.2 (x₁ = 0.010): GUM 100×10⁻⁶ ± 196×10⁻⁶ against the shortest Monte Carlo
    interval (≈ [14, 366]×10⁻⁶), δ = 0.5×10⁻⁶:

    >>> validate_gum(100e-6, 196e-6, (14e-6, 366e-6), 0.5e-6).validated
    False
    """
    return Validation(
        abs(y - expanded - interval[0]), abs(y + expanded - interval[1]), float(delta)
    )


def first_order_u(inputs: Sequence[Input], model: Callable[[np.ndarray], np.ndarray]) -> float:
    """The GUM (first-order) u(y) = √Σ(c_i·u(x_i))² with c_i = ∂f/∂x_i at the estimates by central
    differences of ±u(x_i) (GUM eq. (10), JCGM 101 clause 9 compares it); u(x_i) of a ``"ctrap"``
    input is a/√3, of a ``"t"`` input its scale.

    >>> u = first_order_u([Input("normal", 0.010, 0.005), Input("normal", 0, 0.005)],
    ...                   lambda x: x[0] ** 2 + x[1] ** 2)
    >>> round(u * 1e6, 9)
    100.0
    """
    x = np.array([[i.x] for i in inputs])
    total = 0.0
    for n, item in enumerate(inputs):
        u = item.u / math.sqrt(3.0) if item.distribution == "ctrap" else item.u
        up, down = x.copy(), x.copy()
        up[n] += u
        down[n] -= u
        total += (float(model(up)[0] - model(down)[0]) / 2.0) ** 2
    return math.sqrt(total)


def gum_coverage_probability(k: float) -> float:
    """The coverage probability of y ± k·u for a normal output, p = erf(k/√2) (GUM G.1.3): the
    probability a fixed k stands for (k = 2: 95.45 %).

    >>> round(gum_coverage_probability(2.0), 4)
    0.9545
    """
    return math.erf(k / math.sqrt(2.0))


def model_inputs(draws: np.ndarray, names: Sequence[str]) -> Mapping[str, np.ndarray]:
    """The draws of a run by the inputs' names, for a model written with names.

    >>> model_inputs(np.zeros((2, 3)), ["a", "b"])["b"].shape
    (3,)
    """
    return dict(zip(names, draws))
