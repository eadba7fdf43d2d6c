"""Output writers: plots, manufacturing drawings (CSV, DXF, SVG) and PLC cam tables."""
