"""
The master's sample times from jittered stamps: a delay-locked loop on the master's cycle.

A master axis read by a fieldbus or a PLC task comes on a fixed cycle, but its stamps are often
taken later by a process that is not real-time, and jitter (±0.2 ms at 250 Hz is 5 % of a cycle).
A speed estimate over a short window sees that jitter in full, while the cycle itself is steady for
seconds. The loop follows the cycle with a narrow bandwidth, the master's rate / LOOP_SAMPLES: it
predicts each sample's time one cycle on (a whole number of cycles after lost messages) and moves
the prediction by a fraction of the stamp's error, the period by a smaller one (a second-order
delay-locked loop, F. Adriaensen, "Using a DLL to filter time", 2005, as JACK's audio clock).
It starts with the gains of a least-squares line through all samples so far (the expanding-memory
alpha-beta filter: its time and period are that line's until about the hundredth sample) and
narrows to its own once those are smaller, so it locks within about a hundred samples whatever the
first interval says, for jitter within ±10 % of a cycle (at ±20 %, 13 seeds of 200 locked on a
wrong period from an unlucky first interval until the RESTART rule caught it, within 400 samples;
the positions then fit the stamps better). It counts the samples' cycles: SpeedEstimator fits
positions against them (times cycle x period) or against the stamps, whichever they follow better.
"""
from __future__ import annotations

import math

#: The loop's time constant in samples (bandwidth: the master's rate / LOOP_SAMPLES).
LOOP_SAMPLES = 256
_OMEGA = 2.0 * math.pi / LOOP_SAMPLES
#: Gains of the time and of the period (critically damped: b = sqrt(2) omega, c = omega^2).
_TIME_GAIN, _PERIOD_GAIN = math.sqrt(2.0) * _OMEGA, _OMEGA ** 2
#: Samples after which the start-up gains have narrowed to the loop's own (k = 115): settled.
SETTLED = LOOP_SAMPLES // 2
#: The loop restarts when the rms stamp error passes this fraction of the period (no cycle),
#: or when more than MAX_GAP cycles pass between two samples (the master paused).
RESTART, MAX_GAP = 0.25, 16


class CycleClock:
    """Filter the stamps of a master sampled on a fixed cycle (see the module docstring)."""

    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        """Forget the cycle (after a master loss, or when the stamps do not follow one)."""
        self._origin: int | None = None  # ns; the loop's times are floats after it
        self._time = 0.0  # the loop's time of the last sample, ns after the origin
        self._period = 0.0  # ns, 0 until the second sample
        self._spread = 0.0  # mean square stamp error (ns^2), smoothed like the loop
        self.samples = 0
        self.cycle = 0  # of the last sample, counted from the origin

    @property
    def period(self) -> float:
        """Return the loop's period (ns; 0 before the second sample)."""
        return self._period

    @property
    def exact(self) -> bool:
        """Say whether every stamp since the origin fell on the loop's cycle exactly."""
        return self._spread == 0.0

    def time(self, stamp_ns: int) -> int:
        """Take the next sample's stamp and count its cycle; return the loop's time for it (ns)."""
        if self._origin is None:
            self._origin, self._time, self.samples, self.cycle = stamp_ns, 0.0, 1, 0
            return stamp_ns
        t = float(stamp_ns - self._origin)
        if self._period <= 0.0:
            self._period, self._time, self.samples, self.cycle = t - self._time, t, 2, 1
            return stamp_ns
        cycles = max(1, round((t - self._time) / self._period))
        error = t - (self._time + cycles * self._period)
        self._spread += (error * error - self._spread) / LOOP_SAMPLES
        if self._spread > (RESTART * self._period) ** 2 or cycles > MAX_GAP:
            self.reset()
            return self.time(stamp_ns)
        self.samples += 1
        self.cycle += cycles
        k = self.samples
        self._time += cycles * self._period + max(_TIME_GAIN, 2.0 * (2 * k - 1) / (k * (k + 1))) \
            * error
        self._period += max(_PERIOD_GAIN, 6.0 / (k * (k + 1))) * error / cycles
        return self._origin + round(self._time)
