"""Config: the parameters schema of a cam design and the safe parameters-file reader."""
