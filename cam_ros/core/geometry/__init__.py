"""Geometry: followers, the cam profile (envelope), pressure angle and curvature checks, sizing."""
