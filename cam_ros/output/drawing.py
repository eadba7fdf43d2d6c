"""Export the cam surface for manufacturing: CSV, DXF or SVG, in millimetres, cam frame.

The surface is the cam-frame contact curve of design.geometry(samples), equally spaced in cam
angle from 0, as one closed curve (the last point joins the first): x to the right, y up, cam
centre at the origin.
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


def surface_mm(design: CamDesign, samples: int = EXPORT_SAMPLES) -> np.ndarray:
    """Return the cam surface as an (samples, 2) array of x, y in mm (cam frame)."""
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < MIN_SAMPLES:
        raise InvalidParameter('samples', samples, f'must be an integer >= {MIN_SAMPLES}')
    geometry = design.geometry(samples)
    return np.column_stack((geometry.surface_x, geometry.surface_y)) * MM_PER_M


def write_csv(path: Path, points: np.ndarray) -> None:
    """Write points (mm) as CSV with the header x_mm,y_mm."""
    np.savetxt(path, points, fmt='%.9f', delimiter=',', header=CSV_HEADER, comments='')


def write_dxf(path: Path, points: np.ndarray, unit: str = 'mm', layer: str = DXF_LAYER) -> None:
    """Write points (in unit: mm or in) as one closed LWPOLYLINE on layer, $INSUNITS set."""
    import ezdxf

    document = ezdxf.new('R2010')
    document.header['$INSUNITS'] = DXF_INSUNITS[unit]
    document.header['$MEASUREMENT'] = int(unit == 'mm')  # 1 metric, 0 imperial
    document.layers.add(layer)
    document.modelspace().add_lwpolyline(points.tolist(), format='xy', close=True,
                                         dxfattribs={'layer': layer})
    document.saveas(path)


def write_svg(path: Path, points: np.ndarray) -> None:
    """Write points (mm) as one closed SVG path; the y axis is flipped so the cam reads y up."""
    low = points.min(axis=0) - SVG_MARGIN_MM
    width, height = points.max(axis=0) + SVG_MARGIN_MM - low
    data = ' '.join(f'{x:.6f},{y:.6f}' for x, y in points.tolist())
    path.write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.6f}mm" height="{height:.6f}mm" '
        f'viewBox="{low[0]:.6f} {-(low[1] + height):.6f} {width:.6f} {height:.6f}">\n'
        '  <title>cam surface (mm, cam frame, y up)</title>\n'
        '  <g transform="scale(1,-1)">\n'
        f'    <path id="cam_surface" d="M {data} Z" fill="none" stroke="black" '
        f'stroke-width="{SVG_STROKE_MM}"/>\n'
        '  </g>\n'
        '</svg>\n')


WRITERS: dict[str, Callable[[Path, np.ndarray], None]] = {
    '.csv': write_csv, '.dxf': write_dxf, '.svg': write_svg}


def export_surface(design: CamDesign, path: str | Path, samples: int = EXPORT_SAMPLES) -> int:
    """Write the cam surface to path (.csv, .dxf or .svg, by suffix); return the point count."""
    target = Path(path)
    writer = WRITERS.get(target.suffix.lower())
    if writer is None:
        raise InvalidParameter('path', str(path), 'must end in ' + ', '.join(WRITERS))
    points = surface_mm(design, samples)
    writer(target, points)
    return len(points)
