"""Type stubs of :mod:`subdiv.dask`."""

import os
from typing import Any, Dict, List, Optional, Sequence, Union

PathLike = Union[str, "os.PathLike[str]"]

def map_files(
    paths: Union[PathLike, Sequence[PathLike]],
    out_dir: PathLike,
    command: str,
    client: Optional[Any] = None,
    *,
    resume: bool = True,
    **options: Any,
) -> List[Dict[str, Any]]:
    """Runs ``command`` over ``paths`` on a dask.distributed cluster, one task per mesh."""
