import os
from typing import Any, Callable, Iterable, Optional, Union

def batch(
    inputs: Union[str, os.PathLike[str], Iterable[Union[str, os.PathLike[str]]]],
    out_dir: Union[str, os.PathLike[str]],
    recipe: Optional[str] = None,
    function: Optional[Callable[[Any], Any]] = None,
    client: Any = None,
    *,
    format: str = "ply",
    weld: Union[str, float] = "auto",
    level: int = 3,
    method: str = "rounds",
    n_workers: int = 2,
    shard: Optional[str] = None,
) -> list[dict[str, Any]]: ...
