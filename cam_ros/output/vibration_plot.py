"""Draw a design's elastic-train figures: residual-vibration spectra and the output at speed.

Left: R/a (a the law's amplitude: the stroke, less a ramp's travel) over r = T fn from
SPECTRUM_RANGE of each moving segment's law (Rothbart ch. 13's spectrum, undamped train), the
design's operating points marked. Right: the train's periodic output x over one revolution
against the designed motion s (and the polydyne cam's own motion y when compensated), in the
config's position unit, with x - s on a second axis; for an undamped train at a resonance,
which has no periodic output, a note saying so.
matplotlib's object API only, as in plot.py.
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from cam_ros.core import CamDesign, InvalidParameter
from cam_ros.core.dynamics.periodic import periodic_response
from cam_ros.core.dynamics.vibration import residual_ratio
from cam_ros.output.plot import DPI, FORMATS

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

SPECTRUM_RANGE = (0.5, 10.0)
SPECTRUM_SAMPLES = 2000
FIGURE_SIZE_IN = (14.0, 5.5)
NO_TRAIN = ('needs the follower train: set dynamics.train_natural_frequency or '
            'dynamics.train_stiffness in the config')


def vibration_figure(design: CamDesign, title: str = '') -> Figure:
    """Return the spectra and periodic-output figure of a design with a follower train."""
    from matplotlib.figure import Figure

    train, report = design.config.train, design.vibration_check
    if train is None or report is None:  # the figure is what `cam_ros plot --vibration` asks
        raise InvalidParameter('--vibration', True, NO_TRAIN)
    figure = Figure(figsize=FIGURE_SIZE_IN, layout='constrained')
    spectrum, output = figure.subplots(1, 2, width_ratios=(1.0, 1.3))
    r = np.linspace(*SPECTRUM_RANGE, SPECTRUM_SAMPLES)
    segments = design.surface.segments
    for point in report.segments:
        law = segments[point.index].law
        name = design.program.segments[point.index].law.name
        line, = spectrum.semilogy(r, np.maximum(residual_ratio(law, r), 1e-12), linewidth=1.0,
                                  label=f'segment {point.index}: {name}'
                                        + (' (compensated)' if report.compensated else ''))
        spectrum.plot([point.r], [max(point.residual_ratio, 1e-12)], marker='o',
                      color=line.get_color(), markersize=6, gid='operating point')
    spectrum.set_xlim(*SPECTRUM_RANGE)
    spectrum.set_xlabel('r = segment duration x natural frequency')
    spectrum.set_ylabel('residual amplitude / law amplitude (undamped)')
    spectrum.set_title(f'Residual vibration at {train.natural_frequency:g} Hz '
                       '(dots: this design)', fontsize=10)
    spectrum.grid(True, which='both', linewidth=0.3)
    spectrum.legend(fontsize=8)
    if report.resonance is None:
        _output_panel(design, output)
    else:  # no periodic output to draw: say why on the panel
        output.set_axis_off()
        output.text(0.5, 0.5, 'No steady output: ' + report.resonance_note(), wrap=True,
                    ha='center', va='center', transform=output.transAxes)
    if title:
        figure.suptitle(title)
    return figure


def _output_panel(design: CamDesign, ax: Axes) -> None:
    """Plot the periodic output x against s (and the compensated cam y) over cam angle."""
    train, omega = design.config.train, design.config.cam_speed
    assert train is not None
    unit, factor = design.config.file_position_unit
    response = periodic_response(design.surface, omega, train)
    degrees = np.degrees(response.angle)
    designed = design.program.evaluate(response.angle).s
    ax.plot(degrees, designed * factor, color='0.2', linewidth=1.0, label='designed motion s')
    if design.surface is not design.program:
        ax.plot(degrees, response.input * factor, color='tab:green', linewidth=0.9,
                linestyle='--', label='compensated cam y')
    ax.plot(degrees, response.output * factor, color='tab:blue', linewidth=1.2,
            label='train output x')
    ax.set_xlim(0.0, 360.0)
    ax.set_xticks(np.arange(0.0, 361.0, 30.0))
    ax.set_xlabel('cam angle (deg)')
    ax.set_ylabel(f'position ({unit})')
    ax.grid(True, linewidth=0.3)
    error = ax.twinx()
    error.plot(degrees, (response.output - designed) * factor, color='tab:red', linewidth=0.8,
               label='x - s')
    error.set_ylabel(f'x - s ({unit})', color='tab:red')
    handles = ax.get_legend_handles_labels()
    more = error.get_legend_handles_labels()
    ax.legend(handles[0] + more[0], handles[1] + more[1], loc='upper right', fontsize=8)
    ax.set_title(f'Periodic output at {omega:g} rad/s, damping {train.damping_ratio:g}',
                 fontsize=10)


def plot_vibration(design: CamDesign, path: str | Path, title: str = '') -> Path:
    """Save the vibration figure of a design to a .png or .svg."""
    target = Path(path)
    if target.suffix.lower() not in FORMATS:
        raise InvalidParameter('path', str(path), 'must end in ' + ', '.join(FORMATS))
    vibration_figure(design, title).savefig(target, dpi=DPI)
    return target
