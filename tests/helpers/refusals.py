"""The regex of a whole refusal message, for ``pytest.raises(…, match=whole(message))``.

Every refusal is tested with its whole message: ``match`` is a ``re.search``, so the
message is escaped and anchored at both ends.
"""

import re


def whole(message: str, then: str = "") -> str:
    """A regex matching exactly ``message`` (followed by the regex ``then``, for a tail
    that varies), the whole refusal."""
    return "^" + re.escape(message) + then + "$"


def not_integer(name, span, value):
    """The refusal of an integer parameter outside its domain (``dptbd.errors.check_int``)."""
    return f"{name} must be an integer in {span}, got {value!r}"
