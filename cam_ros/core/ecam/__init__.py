"""Electronic cam maths: following a master axis, handover between designs, cam tables."""
