"""What a streamed run computes over its whole record without holding it, block by block.

Pipeline: results, beside results/streamed_record.py. A :class:`Running` takes each block of a
streamed run (its Dataset, times, skew and kernel diagnostics) and keeps only what the end of the run
needs, in memory that does not grow with the record, except the per-sample series the
statistics are made of (8 bytes per sample and series):

* the extremes from the samples (``<variable>_max`` where the solver's steps do not cover:
  the first and last samples, the samples before a resume, every sample without per-step
  extremes) as running (max, time) pairs — equal to the whole record's, ties included;
* the series of analysis/statistics.py (cage speed, mean squares of skew and pocket force)
  and the sample times: the statistics and their error bars are then computed on the same
  numbers as for an in-memory run;
* sums for the rating life's power means (equal to the whole record's to round-off);
* the plausibility findings over the samples (analysis/guards.py), the worst per check;
* the partial sums and maxima of the run summary (analysis/summary.py) and of the
  engineering lines (analysis/engineering.py).

:meth:`Running.then` joins two parts of one record (the warm-up of a failed run before its
record).
"""

from __future__ import annotations

import numpy as np

from .extremes import EXTREME_VARIABLES, _from_samples, later, sampled_peaks

#: the key of the samples' own peaks among the per-sample series
SAMPLED_PEAKS = "sampled_peaks"


class Running:
    """The running reductions of one record (see the module docstring).

    ``quantities``: the quantities of the extremes to keep (EXTREME_VARIABLES' first column);
    ``cut``: a callable giving the time before which samples count for the extremes (a resumed
    run's resume time; called per block); ``block_checks``: the plausibility checks to run on
    every block."""

    def __init__(self, model, quantities, cut, block_checks):
        self.model, self.quantities, self.cut = model, tuple(quantities), cut
        self.block_checks = tuple(block_checks)
        self.early: dict = {}   # quantity -> pair over the samples before the cut
        self.every: dict = {}   # quantity -> pair over every sample
        self.first: dict | None = None
        self.last: dict | None = None
        self.any_early = False
        self.times: list[np.ndarray] = []
        self.series: dict[str, list[np.ndarray]] = {}
        self.samples = 0
        self.life = None        # (Σ inner, Σ outer) of engineering.lamina_power_sums
        self.ring_sum = 0.0
        self.ran: set = set()
        self.found: list = []
        self.sums: dict = {}    # summary partial sums
        self.maxima: dict = {}  # summary partial maxima (NaN-free arrays or floats)
        self.last_block = None  # the last block's Dataset (the checks on the extremes)
        self.sources = None     # the power loss sources (labels of power_loss_W)
        #: (t, E) of the first and last sample of kinetic_energy_J: the window's ΔE/T
        self.energy_first = self.energy_last = None

    # -- one block -----------------------------------------------------------------------
    def add(self, ds, t, skew, diag) -> None:
        from ..analysis.engineering import lamina_power_sums
        from ..analysis.guards import run_checks, worst_findings
        from ..analysis.statistics import per_sample_series

        t = np.asarray(t, dtype=float)
        samples = {"skew_angle": skew, **diag}
        early = t < self.cut()
        self.any_early |= bool(early.any())
        pairs_e = {q: _from_samples(t[early], samples[q][early]) for q in self.quantities}
        pairs_a = {q: _from_samples(t, samples[q]) for q in self.quantities}
        ends = {q: (_from_samples(t[:1], samples[q][:1]), _from_samples(t[-1:],
                                                                      samples[q][-1:]))
                for q in self.quantities}
        if self.first is None:
            self.first = {q: ends[q][0] for q in self.quantities}
        self.last = {q: ends[q][1] for q in self.quantities}
        for q in self.quantities:
            self.early[q] = later(self.early[q], pairs_e[q]) if q in self.early else pairs_e[q]
            self.every[q] = later(self.every[q], pairs_a[q]) if q in self.every else pairs_a[q]
        self.times.append(t)
        for key, values in per_sample_series(ds).items():
            self.series.setdefault(key, []).append(values)
        # each sample's own peaks over the bearing (40 bytes per sample): the peak trace
        # where no solver step ended between two samples (results/extremes.py)
        self.series.setdefault(SAMPLED_PEAKS, []).append(sampled_peaks(skew, diag))
        sums = lamina_power_sums(self.model.scene, self.model.geometry, diag["contact_force"])
        self.life = sums if self.life is None else (self.life[0] + sums[0],
                                                    self.life[1] + sums[1])
        self.ring_sum += float(np.sum(np.interp(t, self.model.ramp_t, self.model.ramp_w)))
        self.samples += t.size
        ran, found = run_checks(ds, self.model.scene, self.block_checks)
        self.ran |= set(ran)
        self.found = worst_findings(self.found, found)
        self._summary_parts(ds)
        self.last_block = ds

    def _summary_parts(self, ds) -> None:
        from ..analysis.summary import _slice_spread

        def add(key, value):
            self.sums[key] = self.sums.get(key, 0.0) + float(value)

        def most(key, value, smallest=False):
            value = np.asarray(value, dtype=float)
            held = self.maxima.get(key)
            if held is None:
                self.maxima[key] = value
            else:
                self.maxima[key] = (np.fmin if smallest else np.fmax)(held, value)

        if "slip_velocity" in ds and "contact_force" in ds:
            q = ds.contact_force.values
            add("q_abs_slip", np.sum(q * np.abs(ds.slip_velocity.values)))
            add("q", np.sum(q))
        for name in ("slip_velocity", "traction_force"):
            if name in ds:
                most(name + "_spread", _slice_spread(ds[name]))
        if "cage_force" in ds:
            add("cage_force_sq", np.sum(ds.cage_force.values ** 2))
            add("cage_force_n", ds.cage_force.size)
        for name in ("skew_angle", "slip_velocity", "cage_force", "contact_force"):
            if name in ds:
                a = np.abs(ds[name].values)
                most(name + "_absmax", a.max(axis=0))  # per element over the block's samples
        if "lambda_ratio" in ds and np.isfinite(ds.lambda_ratio.values).any():
            most("lambda_min", np.nanmin(ds.lambda_ratio.values), smallest=True)
            if "film_thickness_min" in ds:  # each kept alone too (output.variables)
                most("film_min", np.nanmin(ds.film_thickness_min.values), smallest=True)
        if "power_loss_W" in ds:
            p = np.sum(ds.power_loss_W.values, axis=0)
            self.sums["power"] = self.sums.get("power", 0.0) + p
            self.sources = [str(s) for s in ds.loss_source.values]
            if "drive_power_W" in ds:
                add("drive_power", np.sum(ds.drive_power_W.values))
        if "kinetic_energy_J" in ds and ds.sizes.get("time", 0):
            t, E = ds.time.values, ds.kinetic_energy_J.values
            if self.energy_first is None:
                self.energy_first = (float(t[0]), float(E[0]))
            self.energy_last = (float(t[-1]), float(E[-1]))

    # -- two parts of one record -----------------------------------------------------------
    def then(self, other: "Running") -> "Running":
        """This part followed by ``other`` (a later part of the same record), as one."""
        from ..analysis.guards import worst_findings

        if other.samples == 0:
            return self
        if self.samples == 0:
            return other
        out = Running(self.model, self.quantities, self.cut, self.block_checks)
        for q in self.quantities:
            out.early[q] = later(self.early[q], other.early[q])
            out.every[q] = later(self.every[q], other.every[q])
        out.first, out.last = self.first, other.last
        out.any_early = self.any_early or other.any_early
        out.times = self.times + other.times
        out.series = {k: self.series.get(k, []) + other.series.get(k, [])
                      for k in set(self.series) | set(other.series)}
        out.samples = self.samples + other.samples
        out.life = (self.life[0] + other.life[0], self.life[1] + other.life[1])
        out.ring_sum = self.ring_sum + other.ring_sum
        out.ran = self.ran | other.ran
        out.found = worst_findings(self.found, other.found)
        out.sums = dict(self.sums)
        for k, v in other.sums.items():
            out.sums[k] = out.sums.get(k, 0.0) + v
        out.maxima = dict(self.maxima)
        for k, v in other.maxima.items():
            out.maxima[k] = (v if k not in out.maxima else
                             (np.fmin if k in ("lambda_min", "film_min") else np.fmax)(
                                 out.maxima[k], v))
        out.sources = getattr(other, "sources", getattr(self, "sources", None))
        out.last_block = other.last_block
        out.energy_first = self.energy_first if self.energy_first is not None \
            else other.energy_first
        out.energy_last = other.energy_last if other.energy_last is not None \
            else self.energy_last
        return out

    # -- the end ---------------------------------------------------------------------------
    def sample_pairs(self, with_steps: bool) -> dict:
        """quantity -> (max, time) of the samples the extremes take: with per-step extremes
        the samples before the cut and the first and last; without, every sample."""
        if not with_steps:
            return dict(self.every)
        out = {}
        for q in self.quantities:
            first, last = self.first[q], self.last[q]
            # in time order: the first sample, those before the cut, the last sample
            out[q] = later(later(first, self.early[q]), last)
        return out

    def time_values(self) -> np.ndarray:
        return np.concatenate(self.times) if self.times else np.empty(0)

    def series_values(self) -> dict[str, np.ndarray]:
        return {k: np.concatenate(v) for k, v in self.series.items()}

    def summary(self, digest) -> dict:
        """The run summary (analysis.summary's quantities) from ``digest`` (time, cage speed
        and the extremes of the run) and the partial sums."""
        from ..analysis.summary import summary

        out = summary(digest)
        s, m = self.sums, self.maxima
        if "q" in s:
            with np.errstate(divide="ignore", invalid="ignore"):
                out["load_weighted_slip_m_s"] = float(np.float64(s["q_abs_slip"]) / s["q"])
        for key, name in (("slice_slip_spread_m_s", "slip_velocity_spread"),
                          ("slice_traction_spread_N", "traction_force_spread")):
            if name in m:
                out[key] = float(m[name])
        if s.get("cage_force_n"):
            out["rms_cage_force_N"] = float(np.sqrt(s["cage_force_sq"] / s["cage_force_n"]))
        for key, name in (("max_abs_skew_rad", "skew_angle"),
                          ("max_abs_slip_m_s", "slip_velocity"),
                          ("peak_cage_force_N", "cage_force"),
                          ("peak_slice_load_N", "contact_force")):
            if key not in out and name + "_absmax" in m:
                out[key] = float(np.max(m[name + "_absmax"]))
        if "skew_amplitude_rad" not in out and "skew_angle_absmax" in m:
            out["skew_amplitude_rad"] = float(np.mean(m["skew_angle_absmax"]))
        from ..analysis.summary import SUMMARY_VARIABLES

        return {k: out[k] for k in SUMMARY_VARIABLES if k in out and not np.isnan(out[k])}

    def engineering_lines(self, attrs: dict) -> list[str]:
        from ..analysis.engineering import engineering_lines, window_energy_rate

        m, s = self.maxima, self.sums
        lam = float(m["lambda_min"]) if "lambda_min" in m else None
        h = float(m["film_min"]) if "film_min" in m else None
        power = drive = None
        if "power" in s and self.samples:
            power = dict(zip(self.sources, np.asarray(s["power"]) / self.samples))
            drive = s["drive_power"] / self.samples if "drive_power" in s else None
        rate = (window_energy_rate(self.energy_first, self.energy_last)
                if self.energy_first is not None else None)
        return engineering_lines(attrs, lam, h, power, drive, rate)


def quantities_of(names) -> list[str]:
    """The quantities the extremes ``names`` are kept of."""
    return sorted({EXTREME_VARIABLES[n][0] for n in names})


__all__ = ["Running", "quantities_of"]
