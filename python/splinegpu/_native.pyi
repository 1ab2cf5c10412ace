# The compiled extension (python/src/lib.rs). Its public face is the package's own typed API
# (__init__.pyi); callers inside the package reach it untyped.
from typing import Any

def __getattr__(name: str) -> Any: ...
