"""Export the cam surface for manufacturing: CSV, DXF or SVG, in millimetres, cam frame.

The surface is the cam-frame contact curve (design.contours), equally spaced in cam angle from
0, as one closed curve (the last point joins the first): x to the right, y up, cam centre at the
origin. A groove cam has two, its inner and outer flanks, a conjugate pair its first and second
cam: each is its own closed curve (DXF layer, SVG path, CSV rows named in a third column).
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from cam_ros.core import CamDesign, InvalidParameter

MM_PER_M = 1000.0
#: Default samples per revolution of an export (0.1 deg apart).
EXPORT_SAMPLES = 3600
MIN_SAMPLES = 3
CSV_HEADER = 'x_mm,y_mm'
DXF_LAYER = 'CAM_SURFACE'
DXF_INSUNITS = {'mm': 4, 'in': 1}  # $INSUNITS codes
SVG_MARGIN_MM = 2.0
SVG_STROKE_MM = 0.1


def surfaces_mm(design: CamDesign, samples: int = EXPORT_SAMPLES) -> dict[str, np.ndarray]:
    """Return each working curve of the cam (design.contours) as (samples, 2) x, y in mm."""
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < MIN_SAMPLES:
        raise InvalidParameter('samples', samples, f'must be an integer >= {MIN_SAMPLES}')
    theta = np.linspace(0.0, 2.0 * np.pi, samples, endpoint=False)
    return {name: contour.evaluate(theta)[0].T * MM_PER_M
            for name, contour in design.contours().items()}


def surface_mm(design: CamDesign, samples: int = EXPORT_SAMPLES) -> np.ndarray:
    """Return the cam surface (of a form-closed cam, its first curve) as (samples, 2) mm."""
    return next(iter(surfaces_mm(design, samples).values()))


def write_csv(path: Path, curves: dict[str, np.ndarray]) -> None:
    """Write curves (mm) as CSV, x_mm,y_mm; two or more curves get a third column, its name."""
    if len(curves) == 1:
        np.savetxt(path, next(iter(curves.values())), fmt='%.9f', delimiter=',',
                   header=CSV_HEADER, comments='')
        return
    rows = [f'{x:.9f},{y:.9f},{name}' for name, points in curves.items()
            for x, y in points.tolist()]
    path.write_text('\n'.join([f'{CSV_HEADER},curve', *rows]) + '\n', encoding='utf-8')


def dxf_layer(name: str) -> str:
    """Return the DXF layer of a curve: CAM_SURFACE, or CAM_<NAME> (CAM_INNER, CAM_SECOND)."""
    return DXF_LAYER if name == 'surface' else f'CAM_{name.upper()}'


def write_dxf(path: Path, curves: dict[str, np.ndarray], unit: str = 'mm') -> None:
    """Write each curve (in unit: mm or in) as a closed LWPOLYLINE on its layer, $INSUNITS set.

    Keys are layer names.
    """
    import ezdxf

    document = ezdxf.new('R2010')
    document.header['$INSUNITS'] = DXF_INSUNITS[unit]
    document.header['$MEASUREMENT'] = int(unit == 'mm')  # 1 metric, 0 imperial
    for layer, points in curves.items():
        document.layers.add(layer)
        document.modelspace().add_lwpolyline(points.tolist(), format='xy', close=True,
                                             dxfattribs={'layer': layer})
    document.saveas(path)


def write_svg(path: Path, curves: dict[str, np.ndarray]) -> None:
    """Write curves (mm) as closed SVG paths; the y axis is flipped so the cam reads y up."""
    every = np.concatenate(list(curves.values()))
    low = every.min(axis=0) - SVG_MARGIN_MM
    width, height = every.max(axis=0) + SVG_MARGIN_MM - low
    paths = []
    for name, points in curves.items():
        data = ' '.join(f'{x:.6f},{y:.6f}' for x, y in points.tolist())
        ident = 'cam_surface' if name == 'surface' else f'cam_{name}'
        paths.append(f'    <path id="{ident}" d="M {data} Z" fill="none" stroke="black" '
                     f'stroke-width="{SVG_STROKE_MM}"/>\n')
    path.write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.6f}mm" height="{height:.6f}mm" '
        f'viewBox="{low[0]:.6f} {-(low[1] + height):.6f} {width:.6f} {height:.6f}">\n'
        '  <title>cam surface (mm, cam frame, y up)</title>\n'
        '  <g transform="scale(1,-1)">\n'
        + ''.join(paths) +
        '  </g>\n'
        '</svg>\n')


def _write_dxf_mm(path: Path, curves: dict[str, np.ndarray]) -> None:
    write_dxf(path, {dxf_layer(name): points for name, points in curves.items()})


WRITERS: dict[str, Callable[[Path, dict[str, np.ndarray]], None]] = {
    '.csv': write_csv, '.dxf': _write_dxf_mm, '.svg': write_svg}


def export_surface(design: CamDesign, path: str | Path, samples: int = EXPORT_SAMPLES) -> int:
    """Write the cam surface to path (.csv, .dxf or .svg, by suffix); return the point count."""
    target = Path(path)
    writer = WRITERS.get(target.suffix.lower())
    if writer is None:
        raise InvalidParameter('path', str(path), 'must end in ' + ', '.join(WRITERS))
    curves = surfaces_mm(design, samples)
    writer(target, curves)
    return sum(len(points) for points in curves.values())
