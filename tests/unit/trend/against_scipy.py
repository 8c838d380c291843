#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""trend.AgainstScipy: ncqual_trend's figures against an independent implementation.

Generates a few dozen series with a fixed seed (noisy drifts up and down, flat and constant
series, short series, NaN holes, restarts, one-sided bands, ties, outliers, steps, a series
already beyond its limit), runs them through trend_harness (the library's assess()), and
recomputes every figure here:

  least squares        scipy.stats.linregress (slope, intercept, stderr, intercept_stderr) and
                       the residual sd from NumPy residuals; t from scipy.stats.t.ppf
  prediction interval  the textbook formula in NumPy
  expected date        (limit - a) / b with linregress's a, b
  earliest / latest    scipy.optimize.brentq on the prediction bounds themselves (not the
                       library's quadratic): where the near / far bound meets the limit
  Theil-Sen            scipy.stats.theilslopes(y, x, 0.95, method='separate'): the library
                       matches scipy's default intercept, median(y) - slope * median(x)
  baseline, EWMA,      plain NumPy / Python loops from the textbook definitions
  CUSUM, WE rules,
  capability, warnings
  pass rate            scipy.stats.binomtest(...).proportion_ci(method='wilson')

Usage: against_scipy.py HARNESS. Exit 0 when everything agrees, 1 with the differences, 77 with
"SKIPPED: ..." when SciPy is not importable (run it with Debian's /usr/bin/python3).
"""
import json
import math
import subprocess
import sys

try:
    import numpy as np
    from scipy import optimize, stats
except ImportError as e:  # pragma: no cover
    print(f"SKIPPED: SciPy is not importable by {sys.executable} ({e}); "
          "install python3-scipy (deploy/install-deps.sh --test)")
    sys.exit(77)

NS_PER_DAY = 86400e9
T0 = 1_767_225_600 * 10**9  # 2026-01-01T00:00:00Z
MAX_DAYS = 36525.0
REL = 1e-9  # relative tolerance of every continuous figure

rng = np.random.default_rng(20261125)


# ---------------------------------------------------------------- the series


def daily_times(n, start=T0, jitter_hours=3.0, step_days=1.0):
    """One check a day (or every step_days) at a jittered hour."""
    base = start + (np.arange(n) * step_days * NS_PER_DAY).astype(np.int64)
    jitter = (rng.uniform(-jitter_hours, jitter_hours, n) * 3600e9).astype(np.int64)
    return [int(t) for t in base + jitter]


def series(name, times, values, lower, upper, **extra):
    s = {
        "name": name,
        "times_ns": [int(t) for t in times],
        "values": [None if (v is None or not math.isfinite(v)) else float(v) for v in values],
        "lower": lower,
        "upper": upper,
        "restarts": extra.pop("restarts", []),
        "now_ns": int(extra.pop("now_ns", max(times) + 6 * 3600 * 10**9 if times else T0)),
    }
    last = max(times) if times else T0
    s["predict_at_ns"] = [int(last + d * NS_PER_DAY) for d in (0, 7.5, 30, 90)]
    s.update(extra)
    return s


def make_series():
    out = []
    # Noisy drifts towards the upper and the lower limit (mm), various lengths and noise.
    for i, n in enumerate([12, 20, 40, 60, 120, 260]):
        t = daily_times(n)
        days = (np.array(t) - t[0]) / NS_PER_DAY
        slope = rng.uniform(0.00005, 0.0003)  # 0.05..0.3 µm per day
        noise = rng.uniform(0.0005, 0.003)
        y = 0.001 + slope * days + rng.normal(0, noise, n)
        out.append(series(f"drift_up_{n}", t, y, -0.02, 0.02,
                          verdicts={"pass": int(n) - i, "fail": i, "invalid": 1}))
        y = -0.002 - slope * days + rng.normal(0, noise, n)
        out.append(series(f"drift_down_{n}", t, y, -0.015, 0.025))
    # Strong drifts: the forecast warning, its start, and dates near now.
    for n in (30, 90):
        t = daily_times(n)
        days = (np.array(t) - t[0]) / NS_PER_DAY
        y = 0.004 + 0.0004 * days + rng.normal(0, 0.0008, n)
        out.append(series(f"strong_up_{n}", t, y, -0.02, 0.02 + 0.0004 * n * 0.6))
    # Flat noise: no trend (latest is "never"), and a constant series (no variation).
    for n in (15, 50, 200):
        t = daily_times(n)
        out.append(series(f"flat_{n}", t, rng.normal(0.0, 0.002, n), -0.02, 0.02))
    out.append(series("constant", daily_times(20), [0.003] * 20, -0.01, 0.01))
    # Weak slope against large noise.
    t = daily_times(40)
    days = (np.array(t) - t[0]) / NS_PER_DAY
    out.append(series("weak_slope", t, 0.00002 * days + rng.normal(0, 0.004, 40), -0.02, 0.02))
    # Short series: below and at the minimum.
    for n in (2, 3, 4, 5, 6):
        t = daily_times(n)
        out.append(series(f"short_{n}", t, rng.normal(0.001 * n, 0.001, n), -0.01, 0.01))
    # NaN holes, and ±infinity.
    t = daily_times(45)
    y = 0.0001 * (np.array(t) - t[0]) / NS_PER_DAY + rng.normal(0, 0.001, 45)
    y[[0, 3, 17, 30, 44]] = np.nan
    y[22] = np.inf
    out.append(series("nan_holes", t, y, -0.01, 0.012))
    # Restarts (an intervention, a compensation), one after now, and now before the last point.
    t = daily_times(80)
    days = (np.array(t) - t[0]) / NS_PER_DAY
    y = 0.0002 * (days % 40) + rng.normal(0, 0.0007, 80)
    out.append(series("restarts", t, y, -0.01, 0.012,
                      restarts=[t[10] + 1, t[40] - 3600 * 10**9, t[79] + 10**12]))
    out.append(series("restart_at_point", t, y, -0.01, 0.012, restarts=[t[25]]))
    out.append(series("now_in_past", t, y, -0.01, 0.012, restarts=[t[10] + 1], now_ns=t[60] + 1))
    # One-sided bands: heading to the limit, and heading away (no limit).
    t = daily_times(50)
    days = (np.array(t) - t[0]) / NS_PER_DAY
    up = 0.002 + 0.0001 * days + rng.normal(0, 0.0006, 50)
    out.append(series("upper_only_towards", t, up, None, 0.012))
    out.append(series("upper_only_away", t, -up, None, 0.012))
    out.append(series("lower_only_towards", t, -up, -0.012, None))
    out.append(series("no_limits", t, up, None, None))
    # Angles in rad: small numbers.
    out.append(series("angle_rad", t, 1e-6 * (2 + 0.1 * days + rng.normal(0, 0.5, 50)),
                      -2e-5, 2e-5))
    # Ties: several checks at the same time, values quantised to 0.5 µm.
    t = daily_times(40, jitter_hours=0)
    t = sorted(t + t[5:15])
    days = (np.array(t) - t[0]) / NS_PER_DAY
    y = np.round((0.00008 * days + rng.normal(0, 0.0008, len(t))) / 0.0005) * 0.0005
    out.append(series("ties", t, y, -0.01, 0.01))
    # Unsorted input.
    t = daily_times(30)
    y = 0.0001 * (np.array(t) - t[0]) / NS_PER_DAY + rng.normal(0, 0.001, 30)
    order = rng.permutation(30)
    out.append(series("unsorted", [t[i] for i in order], [y[i] for i in order], -0.01, 0.01))
    # Outliers: Theil-Sen versus least squares.
    t = daily_times(60)
    y = 0.00015 * (np.array(t) - t[0]) / NS_PER_DAY + rng.normal(0, 0.0005, 60)
    y[[7, 33, 51]] += [0.02, -0.015, 0.03]
    out.append(series("outliers", t, y, -0.02, 0.03))
    # A step up after the baseline: EWMA, CUSUM and the rules fire.
    for k, step in enumerate((1.0, 1.5, 2.5)):
        t = daily_times(60)
        y = rng.normal(0, 0.001, 60)
        y[30:] += step * 0.001
        out.append(series(f"step_{k}", t, y, -0.01, 0.01,
                          options={"cusum_k": 0.5, "cusum_h": 4 + k, "ewma_lambda": 0.1 + 0.1 * k}))
    # Already beyond the limit at the last point.
    t = daily_times(25)
    days = (np.array(t) - t[0]) / NS_PER_DAY
    out.append(series("already_beyond", t, 0.0005 * days + rng.normal(0, 0.0005, 25), -0.01,
                      0.008))
    # A significant but tiny drift against a wide band: the dates are more than 100 years off.
    t = daily_times(60)
    days = (np.array(t) - t[0]) / NS_PER_DAY
    out.append(series("far_limit", t, 1e-7 * days + rng.normal(0, 1e-6, 60), -1.0, 1.0))
    # Other options: baseline of 5, a longer horizon, a 4-point minimum.
    t = daily_times(35)
    days = (np.array(t) - t[0]) / NS_PER_DAY
    out.append(series("options", t, 0.0003 * days + rng.normal(0, 0.001, 35), -0.02, 0.02,
                      options={"baseline_points": 5, "min_points": 4, "horizon_days": 90}))
    # Weekly checks for two years.
    t = daily_times(104, step_days=7, jitter_hours=12)
    days = (np.array(t) - t[0]) / NS_PER_DAY
    out.append(series("weekly", t, 0.00003 * days + rng.normal(0, 0.002, 104), -0.03, 0.03))
    # Nothing at all, and only NaN.
    out.append(series("empty", [], [], -0.01, 0.01))
    out.append(series("all_nan", daily_times(8), [float("nan")] * 8, -0.01, 0.01))
    # Magnitudes toleranced [0, U] (docs/trends.md, "One-sided metrics"): one that improves
    # (a step down after the baseline: no rule, EWMA or CUSUM may warn below, no forecast towards
    # 0) and one that drifts up to U.
    tm = daily_times(60)
    dm = (np.array(tm) - tm[0]) / NS_PER_DAY
    mag = np.abs(0.006 + rng.normal(0, 0.001, 60))
    mag[30:] -= 0.003
    out.append(series("magnitude_improves", tm, mag, 0.0, 0.015))
    out.append(series("magnitude_towards", tm, 0.004 + 0.0001 * dm + np.abs(
        rng.normal(0, 0.0006, 60)), 0.0, 0.012))
    return out


# ---------------------------------------------------------------- the independent figures


class Report:
    def __init__(self):
        self.failures = []
        self.max_dev = {}  # quantity -> max relative deviation seen
        self.checked = 0

    def num(self, where, what, got, want, scale=0.0, rel=REL):
        """got ~ want within rel * max(|got|, |want|, scale)."""
        self.checked += 1
        if want is None or (isinstance(want, float) and not math.isfinite(want)):
            if got is not None:
                self.failures.append(f"{where}: {what} = {got}, expected none")
            return
        if got is None:
            self.failures.append(f"{where}: {what} missing, expected {want!r}")
            return
        denom = max(abs(got), abs(want), scale)
        dev = abs(got - want) / denom if denom > 0 else 0.0
        self.max_dev[what] = max(self.max_dev.get(what, 0.0), dev)
        if dev > rel:
            self.failures.append(f"{where}: {what} = {got!r}, expected {want!r} (rel {dev:.3g})")

    def same(self, where, what, got, want):
        self.checked += 1
        if got != want:
            self.failures.append(f"{where}: {what} = {got!r}, expected {want!r}")


def segment_of(s):
    now = s["now_ns"]
    restarts = [r for r in s["restarts"] if r <= now]
    restart = max(restarts) if restarts else None
    pts, skipped = [], 0
    for t, v in zip(s["times_ns"], s["values"]):
        if t > now or (restart is not None and t <= restart):
            continue
        if v is None or not math.isfinite(v):
            skipped += 1
        else:
            pts.append((t, v))
    pts.sort(key=lambda p: p[0])  # stable, as the library's
    return pts, skipped


def t_quantile(df):
    """The 0.975 quantile of Student's t, to double precision.

    SciPy 1.10's t.ppf (cdflib's stdtrit) is good to about 1e-9 relative only (for df = 48 its
    quantile has t.sf - 0.025 = 1.6e-10; SciPy later moved stdtrit to Boost, scipy PR #22962).
    One Newton step on SciPy's own t.sf and t.pdf (Cephes, accurate to ~1e-16) brings it to
    double precision, independently of the library's Boost.Math.
    """
    q = stats.t.ppf(0.975, df)
    return q + (stats.t.sf(q, df) - 0.025) / stats.t.pdf(q, df)


def days_of(times, ref):
    return np.array([float(t - ref) / NS_PER_DAY for t in times])


def ns_at(ref, x):
    return ref + int(round(x * NS_PER_DAY))


def check_date(rep, where, what, got, status, x, ref, last_x):
    """A LimitDate: status, and the date within REL of its distance from the reference."""
    rep.same(where, what + ".status", got["status"], status)
    if status in ("date", "already_beyond") and x is not None and got["time_ns"] is not None:
        gx = (got["time_ns"] - ref) / NS_PER_DAY
        rep.num(where, what + " (days)", gx, x, scale=max(abs(last_x), 1.0))
    elif status in ("never", "no_trend", "no_limit", "too_far", "not_enough_points"):
        rep.same(where, what + ".time_ns", got["time_ns"], None)


def first_root(f, lo, last_x):
    """Smallest x >= lo with f(x) >= 0, for f rising without end from below at lo (brentq)."""
    step = 1.0
    hi = lo + step
    while f(hi) < 0:
        step *= 2
        hi = lo + step
        if hi - last_x > 4 * MAX_DAYS:
            return None
    return optimize.brentq(f, lo, hi, xtol=1e-13, rtol=4 * np.finfo(float).eps, maxiter=500)


def forecast_figures(pts, lower, upper, min_points, now_ns=None, horizon=None):
    """The least-squares forecast of a list of (t, v), independently of the library."""
    n = len(pts)
    if n < min_points:
        return None
    ref = pts[0][0]
    x = days_of([p[0] for p in pts], ref)
    y = np.array([p[1] for p in pts])
    if np.ptp(x) == 0:
        return None
    lr = stats.linregress(x, y)
    a, b = lr.intercept, lr.slope
    if np.ptp(y) == 0:
        # A constant series: the exact line is flat through it. linregress leaves a rounding
        # residue (slope ~1e-20, a "heading") from np.mean's last bit; the library does not.
        a, b = float(y[0]), 0.0
    resid = y - (a + b * x)
    s = math.sqrt(float(np.sum(resid**2)) / (n - 2))
    xbar = float(np.mean(x))
    sxx = float(np.sum((x - xbar) ** 2))
    se_b = s / math.sqrt(sxx)
    t = t_quantile(n - 2)
    lo, hi = b - t * se_b, b + t * se_b
    trend = lo > 0 or hi < 0
    last_x = float(x[-1])
    f = dict(ref=ref, x=x, y=y, lr=lr, a=a, b=b, s=s, xbar=xbar, sxx=sxx, se_b=se_b, t=t, lo=lo,
             hi=hi, trend=trend, last_x=last_x, n=n, last_ns=pts[-1][0])
    heading = "above" if b > 0 else "below" if b < 0 else None
    limit = None
    if heading == "above" and upper is not None:
        limit = upper
    if heading == "below" and lower is not None:
        limit = lower
    f["heading"], f["limit"] = heading, limit

    def half(xx):
        return t * s * math.sqrt(1 + 1 / n + (xx - xbar) ** 2 / sxx)

    f["half"] = half
    # expected
    if heading is None:
        f["expected"] = ("no_trend", None)
    elif limit is None:
        f["expected"] = ("no_limit", None)
    elif not trend:
        f["expected"] = ("no_trend", None)
    else:
        xc = (limit - a) / b
        if xc <= last_x:
            f["expected"] = ("already_beyond", xc if last_x - xc <= MAX_DAYS else None)
        elif xc - last_x > MAX_DAYS:
            f["expected"] = ("too_far", None)
        else:
            f["expected"] = ("date", xc)
    # earliest and latest, by root finding on the bounds themselves (mirrored to head up)
    if heading is None or limit is None:
        st = "no_trend" if heading is None else "no_limit"
        f["earliest"] = f["latest"] = (st, None)
    else:
        sg = 1.0 if heading == "above" else -1.0

        def near(xx):
            return sg * (a + b * xx) + half(xx) - sg * limit

        def far(xx):
            return sg * (a + b * xx) - half(xx) - sg * limit

        if near(last_x) >= 0:
            f["earliest"] = ("already_beyond", last_x)
        else:
            r = first_root(near, last_x, last_x)
            if r is None:
                f["earliest"] = ("too_far", None)
            elif r - last_x > MAX_DAYS:
                f["earliest"] = ("too_far", None)
            else:
                f["earliest"] = ("date", r)
        if not (abs(b) > t * se_b):
            f["latest"] = ("never", None)
        elif far(last_x) >= 0:
            f["latest"] = ("already_beyond", last_x)
        else:
            r = first_root(far, last_x, last_x)
            if r is None or r - last_x > MAX_DAYS:
                f["latest"] = ("too_far", None)
            else:
                f["latest"] = ("date", r)
    if now_ns is not None:
        st, ex = f["earliest"]
        active = (trend and heading is not None and st in ("date", "already_beyond") and
                  (ns_at(ref, ex) - now_ns) / NS_PER_DAY <= horizon)
        f["warning"] = heading if active else None
    return f


def check_forecast(rep, s, got, pts, lower, upper, opts):
    where = s["name"]
    min_points = opts.get("min_points", 5)
    f = forecast_figures(pts, lower, upper, min_points)
    if f is None:
        rep.same(where, "forecast.error non-empty", bool(got["error"]), True)
        rep.same(where, "forecast.earliest", got["earliest"]["status"], "not_enough_points")
        return None
    rep.same(where, "forecast.error", got["error"], "")
    ys = float(np.std(f["y"])) or 1e-3
    xs = float(np.ptp(f["x"]))
    rep.same(where, "forecast.reference_ns", got["reference_ns"], f["ref"])
    rep.num(where, "slope (linregress)", got["slope"], f["b"], scale=ys / xs)
    rep.num(where, "intercept (linregress)", got["intercept"], f["a"], scale=ys)
    constant = np.ptp(f["y"]) == 0
    rep.num(where, "slope_se (linregress stderr)", got["slope_se"],
            0.0 if constant else f["lr"].stderr, scale=1e-6 * ys / xs)
    rep.num(where, "intercept_se (linregress)", got["intercept_se"],
            0.0 if constant else f["lr"].intercept_stderr, scale=1e-6 * ys)
    rep.num(where, "residual_sd", got["residual_sd"], f["s"], scale=1e-6 * ys)
    rep.num(where, "t quantile (t.ppf, refined)", got["t_quantile"], f["t"])
    rep.num(where, "t quantile (t.ppf as is)", got["t_quantile"], stats.t.ppf(0.975, f["n"] - 2),
            rel=1e-8)
    rep.num(where, "slope_low", got["slope_low"], f["lo"], scale=ys / xs)
    rep.num(where, "slope_high", got["slope_high"], f["hi"], scale=ys / xs)
    rep.same(where, "trend", got["trend"], f["trend"])
    rep.same(where, "heading", got["heading"], f["heading"])
    for p in got["predictions"]:
        xx = (p["time_ns"] - f["ref"]) / NS_PER_DAY
        fit = f["a"] + f["b"] * xx
        h = f["half"](xx)
        rep.num(where, "prediction fitted", p["fitted"], fit, scale=ys)
        rep.num(where, "prediction lower", p["lower"], fit - h, scale=ys)
        rep.num(where, "prediction upper", p["upper"], fit + h, scale=ys)
    for what in ("expected", "earliest", "latest"):
        st, xx = f[what]
        check_date(rep, where, what, got[what], st, xx, f["ref"], f["last_x"])
    return f


def check_theil_sen(rep, s, got, pts, lower, upper, opts):
    where = s["name"]
    if len(pts) < opts.get("min_points", 5):
        rep.same(where, "theil_sen.error non-empty", bool(got["error"]), True)
        return
    ref = pts[0][0]
    x = days_of([p[0] for p in pts], ref)
    y = np.array([p[1] for p in pts])
    if np.ptp(x) == 0:
        rep.same(where, "theil_sen.error non-empty", bool(got["error"]), True)
        return
    r = stats.theilslopes(y, x, 0.95, method="separate")
    ys = float(np.std(y)) or 1e-3
    xs = float(np.ptp(x))
    rep.num(where, "theil_sen slope", got["slope"], r.slope, scale=ys / xs)
    rep.num(where, "theil_sen intercept", got["intercept"], r.intercept, scale=ys)
    rep.num(where, "theil_sen low_slope", got["slope_low"], r.low_slope, scale=ys / xs)
    rep.num(where, "theil_sen high_slope", got["slope_high"], r.high_slope, scale=ys / xs)
    trend = r.low_slope > 0 or r.high_slope < 0
    rep.same(where, "theil_sen trend", got["trend"], bool(trend))
    b = r.slope
    heading = "above" if b > 0 else "below" if b < 0 else None
    limit = upper if heading == "above" else lower if heading == "below" else None
    last_x = float(x[-1])
    if heading is None:
        want = ("no_trend", None)
    elif limit is None:
        want = ("no_limit", None)
    elif not trend:
        want = ("no_trend", None)
    else:
        xc = (limit - r.intercept) / b
        if xc <= last_x:
            want = ("already_beyond", xc)
        elif xc - last_x > MAX_DAYS:
            want = ("too_far", None)
        else:
            want = ("date", xc)
    check_date(rep, where, "theil_sen expected", got["expected"], want[0], want[1], ref, last_x)


def spc_figures(values, opts):
    nb = opts.get("baseline_points", 10)
    if len(values) < nb:
        return None
    base = np.array(values[:nb])
    mr = float(np.mean(np.abs(np.diff(base))))
    mean = float(np.mean(base))
    sigma = mr / 1.128
    if not sigma > 0:
        return None
    return dict(mean=mean, mr=mr, sigma=sigma, sd=float(np.std(base, ddof=1)))


def judged(lower, upper):
    # A magnitude [0, U] is the one-sided band (-inf, U]: its 0 is where values end.
    if lower == 0 and upper is not None and upper > 0:
        return None, upper
    return lower, upper


def watched(lower, upper):
    # The side a one-sided metric can go wrong on: its rules, EWMA and CUSUM warn there only.
    lower, upper = judged(lower, upper)
    if upper is not None and lower is None:
        return "above"
    if lower is not None and upper is None:
        return "below"
    return None


def we_rules(values, mean, sigma, only=None):
    z = [(v - mean) / sigma for v in values]
    out = []
    for j in range(len(z)):
        for rule, window, need, k in ((1, 1, 1, 3.0), (2, 3, 2, 2.0), (3, 5, 4, 1.0),
                                      (4, 8, 8, 0.0)):
            if j + 1 < window:
                continue
            w = z[j + 1 - window:j + 1]
            if sum(1 for v in w if v > k) >= need and only != "below":
                out.append([rule, j, "above"])
            elif sum(1 for v in w if v < -k) >= need and only != "above":
                out.append([rule, j, "below"])
    return out


def check_spc(rep, s, got, values, opts, only=None):
    where = s["name"]
    base = spc_figures(values, opts)
    if base is None:
        rep.same(where, "baseline.error non-empty", bool(got["baseline"]["error"]), True)
        rep.same(where, "rules", got["rules"], [])
        return None
    g = got["baseline"]
    rep.same(where, "baseline.error", g["error"], "")
    sc = base["sigma"]
    rep.num(where, "baseline mean", g["mean"], base["mean"], scale=sc)
    rep.num(where, "baseline sigma_within", g["sigma_within"], base["sigma"])
    rep.num(where, "baseline sigma_overall", g["sigma_overall"], base["sd"])
    rep.num(where, "baseline UCL", g["ucl"], base["mean"] + 3 * base["sigma"], scale=sc)
    rep.num(where, "baseline LCL", g["lcl"], base["mean"] - 3 * base["sigma"], scale=sc)
    rules = we_rules(values, base["mean"], base["sigma"], only)
    rep.same(where, "Western Electric signals", got["rules"], rules)
    # EWMA
    lam = opts.get("ewma_lambda", 0.2)
    width = opts.get("ewma_width", 3.0)
    z, zs, lows, ups, first = base["mean"], [], [], [], None
    for i, v in enumerate(values, start=1):
        z = lam * v + (1 - lam) * z
        h = width * base["sigma"] * math.sqrt(lam / (2 - lam) * (1 - (1 - lam) ** (2 * i)))
        zs.append(z)
        lows.append(base["mean"] - h)
        ups.append(base["mean"] + h)
        if first is None and (z > base["mean"] + h or z < base["mean"] - h):
            first = i - 1
    e = got["ewma"]
    for i in range(len(values)):
        rep.num(where, "EWMA z", e["z"][i], zs[i], scale=sc)
        rep.num(where, "EWMA limits", e["lower"][i], lows[i], scale=sc)
        rep.num(where, "EWMA limits", e["upper"][i], ups[i], scale=sc)
    rep.same(where, "EWMA first signal", e["first_signal"], first)
    # CUSUM
    K = opts.get("cusum_k", 0.5) * base["sigma"]
    H = opts.get("cusum_h", 5.0) * base["sigma"]
    cp = cm = 0.0
    np_ = nm = 0
    c = got["cusum"]
    fu = fd = mu = md = None
    ups_c, downs_c = [], []
    for i, v in enumerate(values):
        cp = max(0.0, v - (base["mean"] + K) + cp)
        cm = max(0.0, (base["mean"] - K) - v + cm)
        np_ = np_ + 1 if cp > 0 else 0
        nm = nm + 1 if cm > 0 else 0
        ups_c.append(cp)
        downs_c.append(cm)
        rep.num(where, "CUSUM C+/C-", c["upper"][i], cp, scale=sc)
        rep.num(where, "CUSUM C+/C-", c["lower"][i], cm, scale=sc)
        rep.same(where, "CUSUM N+", c["upper_count"][i], np_)
        rep.same(where, "CUSUM N-", c["lower_count"][i], nm)
        if fu is None and cp > H:
            fu, mu = i, base["mean"] + K + cp / np_
        if fd is None and cm > H:
            fd, md = i, base["mean"] - K - cm / nm
    rep.same(where, "CUSUM first up", c["first_up"], fu)
    rep.same(where, "CUSUM first down", c["first_down"], fd)
    rep.num(where, "CUSUM shifted mean", c["mean_at_first_up"], mu, scale=sc)
    rep.num(where, "CUSUM shifted mean", c["mean_at_first_down"], md, scale=sc)
    # Per point: which condition holds (for the warnings).
    n = len(values)
    tracks = {k: [None] * n for k in ("control_limit", "western_electric_2", "western_electric_3",
                                      "western_electric_4", "ewma", "cusum_up", "cusum_down")}
    names = {1: "control_limit", 2: "western_electric_2", 3: "western_electric_3",
             4: "western_electric_4"}
    for rule, j, side in rules:
        tracks[names[rule]][j] = side
    for i in range(n):
        if zs[i] > ups[i] and only != "below":
            tracks["ewma"][i] = "above"
        elif zs[i] < lows[i] and only != "above":
            tracks["ewma"][i] = "below"
        if ups_c[i] > H and only != "below":
            tracks["cusum_up"][i] = "above"
        if downs_c[i] > H and only != "above":
            tracks["cusum_down"][i] = "below"
    return tracks


def check_capability(rep, s, got, values, lower, upper, opts):
    where = s["name"]
    if len(values) < max(opts.get("min_points", 5), 2):
        rep.same(where, "capability.error non-empty", bool(got["error"]), True)
        return
    v = np.array(values)
    mean = float(np.mean(v))
    sw = float(np.mean(np.abs(np.diff(v)))) / 1.128
    so = float(np.std(v, ddof=1)) if np.ptp(v) > 0 else 0.0  # np.std's residue: see above
    rep.num(where, "capability mean", got["mean"], mean, scale=so or 1e-3)
    rep.num(where, "capability sigma_within", got["sigma_within"], sw, scale=1e-9)
    rep.num(where, "capability sigma_overall", got["sigma_overall"], so, scale=1e-9)
    for sig, names in ((sw, ("cp", "cpk", "cpu", "cpl")), (so, ("pp", "ppk", "ppu", "ppl"))):
        want = dict.fromkeys(names)
        if sig > 0:
            if upper is not None:
                want[names[2]] = (upper - mean) / (3 * sig)
            if lower is not None:
                want[names[3]] = (mean - lower) / (3 * sig)
            if upper is not None and lower is not None:
                want[names[0]] = (upper - lower) / (6 * sig)
            sides = [w for w in (want[names[2]], want[names[3]]) if w is not None]
            want[names[1]] = min(sides) if sides else None
        for k in names:
            rep.num(where, "capability " + k, got[k], want[k], scale=1.0)


def check_warnings(rep, s, got, pts, tracks, lower, upper, opts):
    where = s["name"]
    want = []
    n = len(pts)
    if tracks is not None and n:
        for kind, track in tracks.items():
            side = track[-1]
            if side is None:
                continue
            since = n - 1
            while since > 0 and track[since - 1] == side:
                since -= 1
            want.append({"kind": kind, "side": side, "since_index": since,
                         "since_ns": pts[since][0], "expected_ns": None, "earliest_ns": None})
    horizon = opts.get("horizon_days", 30.0)
    min_points = opts.get("min_points", 5)
    f = forecast_figures(pts, lower, upper, min_points, s["now_ns"], horizon)
    if f is not None and f["warning"]:
        side = f["warning"]
        since = n - 1
        while since > 0:
            g = forecast_figures(pts[:since], lower, upper, min_points, pts[since - 1][0], horizon)
            if g is None or g["warning"] != side:
                break
            since -= 1
        w = {"kind": "forecast", "side": side, "since_index": since, "since_ns": pts[since][0]}
        want.append(w)
    order = ["control_limit", "western_electric_2", "western_electric_3", "western_electric_4",
             "ewma", "cusum_up", "cusum_down", "forecast"]
    want.sort(key=lambda w: order.index(w["kind"]))
    rep.same(where, "warning kinds", [(w["kind"], w["side"], w["since_index"]) for w in got],
             [(w["kind"], w["side"], w["since_index"]) for w in want])
    for g, w in zip(got, want):
        rep.same(where, "warning since_ns", g["since_ns"], w["since_ns"])
        if w["kind"] == "forecast":
            st, xx = f["earliest"]
            rep.num(where, "warning earliest (days)", (g["earliest_ns"] - f["ref"]) / NS_PER_DAY,
                    xx, scale=max(f["last_x"], 1.0))
            st, xx = f["expected"]
            if xx is not None and g["expected_ns"] is not None:
                rep.num(where, "warning expected (days)",
                        (g["expected_ns"] - f["ref"]) / NS_PER_DAY, xx,
                        scale=max(f["last_x"], 1.0))
    return [w["kind"] for w in want]


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    all_series = make_series()
    proc = subprocess.run([sys.argv[1]], input=json.dumps({"series": all_series}),
                          capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        print(f"trend_harness failed ({proc.returncode}): {proc.stderr}")
        return 1
    results = {r["name"]: r for r in json.loads(proc.stdout)["series"]}
    rep = Report()
    fired = {}
    for s in all_series:
        got = results[s["name"]]
        opts = s.get("options", {})
        pts, skipped = segment_of(s)
        rep.same(s["name"], "segment times", got["segment_times_ns"], [p[0] for p in pts])
        rep.same(s["name"], "skipped", got["skipped"], skipped)
        values = [p[1] for p in pts]
        only = watched(s["lower"], s["upper"])
        lower, upper = judged(s["lower"], s["upper"])
        check_forecast(rep, s, got["forecast"], pts, lower, upper, opts)
        check_theil_sen(rep, s, got["theil_sen"], pts, lower, upper, opts)
        tracks = check_spc(rep, s, got, values, opts, only)
        check_capability(rep, s, got["capability"], values, lower, upper, opts)
        for kind in check_warnings(rep, s, got["warnings"], pts, tracks, lower, upper, opts):
            fired[kind] = fired.get(kind, 0) + 1
        if "verdicts" in s:
            v = s["verdicts"]
            k, n = v["pass"], v["pass"] + v["fail"]
            ci = stats.binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
            rep.num(s["name"], "pass rate", got["pass_rate"]["rate"], k / n)
            rep.num(s["name"], "pass rate Wilson bounds", got["pass_rate"]["lower"], ci.low)
            rep.num(s["name"], "pass rate Wilson bounds", got["pass_rate"]["upper"], ci.high)
    statuses = {}
    for r in results.values():
        for what in ("expected", "earliest", "latest"):
            st = r["forecast"][what]["status"]
            statuses[st] = statuses.get(st, 0) + 1
    print(f"{len(all_series)} series, {rep.checked} figures compared (relative tolerance {REL:g})")
    print("largest relative deviations:")
    for what in sorted(rep.max_dev):
        print(f"  {what:34s} {rep.max_dev[what]:.3g}")
    print("date statuses seen:", dict(sorted(statuses.items())))
    print("active warnings seen:", dict(sorted(fired.items())))
    # The data must exercise what it claims to: each warning kind and each date status.
    for kind in ("control_limit", "ewma", "cusum_up", "cusum_down", "western_electric_4",
                 "forecast"):
        if kind not in fired:
            rep.failures.append(f"no series has an active {kind} warning: the data tests nothing")
    for st in ("date", "already_beyond", "never", "no_trend", "no_limit", "too_far",
               "not_enough_points"):
        if st not in statuses:
            rep.failures.append(f"no series gives a '{st}' date: the data tests nothing")
    if rep.failures:
        print(f"{len(rep.failures)} differences:")
        for f in rep.failures[:60]:
            print("  " + (f if len(f) <= 300 else f[:300] + " ..."))
        return 1
    print("OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
