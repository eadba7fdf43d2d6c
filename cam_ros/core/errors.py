"""The one error root of cam_ros and its few meaningful subclasses."""


class CamError(Exception):
    """Root of every error cam_ros raises on purpose."""


class InvalidParameter(CamError, ValueError):
    """A design parameter broke a rule; names the parameter, the value and the rule."""

    def __init__(self, parameter: str, value: object, rule: str):
        self.parameter = parameter
        self.value = value
        self.rule = rule
        super().__init__(f'{parameter} = {value!r}: {rule}')


class RecordingError(CamError, OSError):
    """A recording could not be written or read."""
