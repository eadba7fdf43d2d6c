"""Motion: normalised motion laws, polynomial solves, programs of segments over the cam angle."""
