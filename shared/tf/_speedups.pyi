from collections.abc import Callable

from ..msgs.geometry_msgs import TransformStamped
from .chain import Step
from .rigid import Tf

def evaluate(
    src_pre: Tf | None, src: list[Step], tgt_pre: Tf | None, tgt: list[Step], t: int, /
) -> Tf | None: ...
COMPACT_AT: int

def latest(dyn: list[list[int]], /) -> int: ...

def bind(*types: type) -> None: ...

class Inserter:
    watchers: int
    def __init__(
        self,
        caches: dict[str, object],
        authority: dict[str, str],
        lock: object,
        cache_ns: int,
        fallback: Callable[..., bool],
    ) -> None: ...
    def __call__(
        self, transform: TransformStamped, authority: str = ..., *, strict: bool = ...
    ) -> bool: ...
