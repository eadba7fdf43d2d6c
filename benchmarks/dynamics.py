"""
The cost of follower dynamics: the same design with and without a follower train, side by side.

The design with dynamics is the benchmarked config plus the DYNAMICS blocks below (a spring-held
roller train and its Hertz contact); everything else, the motion and the follower, is the same.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from benchmarks.core import angles
from benchmarks.report import Figure, Target
from benchmarks.timing import interleaved_medians
from cam_ros.core import CamDesign, build_design, parse_parameters, read_parameters_file
from cam_ros.core.report import design_report

#: The issue's target: dynamics add at most 25 % to evaluate and to the 1-angle service p50.
DYNAMICS_TARGET = Target('<=', 1.25)
#: Added to the benchmarked config (SI; face width in its length unit).
DYNAMICS = {'dynamics': {'mass': 0.5, 'spring_rate': 2000.0, 'spring_preload': 20.0,
                         'damping_ratio': 0.05},
            'contact': {'face_width': 1.0}}


def dynamics_design(config: Path) -> CamDesign:
    """Return the design of config with the DYNAMICS follower train added."""
    flat = read_parameters_file(config)
    flat.update((f'{section}.{key}', value) for section, values in DYNAMICS.items()
                for key, value in values.items())
    return build_design(parse_parameters(flat))


def write_dynamics_config(config: Path, target: Path) -> Path:
    """Write config with the DYNAMICS blocks added as a params file for cam_node."""
    document: dict[str, Any] = yaml.safe_load(config.read_text())
    parameters = next(iter(document.values()))['ros__parameters']
    for section, values in DYNAMICS.items():
        parameters.setdefault(section, {}).update(values)
    target.write_text(yaml.safe_dump(document))
    return target


def evaluate_figure(config: Path, design: CamDesign, count: int, repeats: int) -> Figure:
    """Time CamDesign.evaluate at count angles with and without dynamics, interleaved."""
    theta = angles(count)
    dynamic = dynamics_design(config)
    times = interleaved_medians({'without': lambda: design.evaluate(theta),
                                 'with': lambda: dynamic.evaluate(theta)}, repeats)
    return Figure(
        'design_evaluate_dynamics_ms', f'CamDesign.evaluate with dynamics; N = {count:,}',
        times['with'] * 1e-6, 'ms', 'without dynamics', times['without'] * 1e-6,
        DYNAMICS_TARGET,
        'The same design with a spring-held follower train (benchmarks/dynamics.py): contact '
        'force, camshaft torque and Hertz contact stress added to the evaluation.')


def service_figure(p50_with: float, p50_without: float, calls: int) -> Figure:
    """Return the 1-angle service p50 of a cam_node with dynamics against one without."""
    return Figure(
        'service_dynamics_p50_ms', '/cam/evaluate with dynamics, 1 angle, p50', p50_with, 'ms',
        'without dynamics, p50', p50_without, DYNAMICS_TARGET,
        f'Two cam_node processes on the same design, one with the follower train of '
        f'benchmarks/dynamics.py, called in alternating blocks ({calls} calls each).')


#: The issue's target: a follower train's vibration figures add at most 25 % to the report.
VIBRATION_TARGET = Target('<=', 1.25)
#: Added to the benchmarked config: a follower train of 6 Hz (6 x the default cam's frequency).
TRAIN = {'dynamics.train_natural_frequency': 6.0, 'dynamics.train_damping_ratio': 0.05}


def vibration_figure(config: Path, design: CamDesign, repeats: int) -> Figure:
    """Time the design report with and without a follower train, interleaved."""
    flat = read_parameters_file(config)
    flat.update(TRAIN)
    elastic = build_design(parse_parameters(flat))

    def report(cam: CamDesign) -> object:
        fresh = CamDesign(cam.config, cam.program, cam.follower)  # nothing cached
        return design_report(fresh), fresh.vibration_check
    times = interleaved_medians({'rigid': lambda: report(design),
                                 'elastic': lambda: report(elastic)}, repeats)
    return Figure(
        'design_report_vibration_ms', 'design_report with a follower train (vibration figures)',
        times['elastic'] * 1e-6, 'ms', 'design_report, rigid train', times['rigid'] * 1e-6,
        VIBRATION_TARGET,
        'The default design with a 6 Hz train: residual vibration per segment (quadrature), '
        'the exact periodic response (8,192 stretches) and its refined extremes.')
