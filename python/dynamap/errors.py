"""The exceptions of dynamap: each carries the line `dynamap map` prints for the same failure,
and the exit status the command would end with (``exit_status``)."""


class Error(RuntimeError):
    """A run that failed: an output that cannot be written, a damaged input, ..."""

    exit_status = 1


class UsageError(Error, ValueError):
    """A bad argument (what the command calls a bad command line)."""

    exit_status = 2


class ConfigError(Error, ValueError):
    """A bad configuration file: the message names file, section and key."""

    exit_status = 3


class InputError(Error):
    """The input cannot be read at all (missing, not a log, no scan with a pose)."""

    exit_status = 1


class DynamapWarning(UserWarning):
    """What `dynamap map` prints as a warning: records or scans skipped, an input that ended in
    a fault (the result then covers the scans before it)."""
