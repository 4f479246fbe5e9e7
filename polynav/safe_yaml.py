"""Safe YAML reading through libyaml where PyYAML was built with it.

PyYAML's pure-Python safe loader takes ~90 ms over the demo world's 9 kB file; libyaml's
(``CSafeLoader``) reads the same document the same way in ~10 ms. Worlds, robot profiles and
map descriptors are read at every start-up and every runtime built, so polynav always reads
through here. Errors are ``yaml.YAMLError`` either way.
"""

from __future__ import annotations

from typing import Any

import yaml

_LOADER: type[yaml.SafeLoader] = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def load(text: str | bytes) -> Any:
    """``yaml.safe_load``, through libyaml when it is there."""
    return yaml.load(text, Loader=_LOADER)  # noqa: S506 - a safe loader, C or Python
