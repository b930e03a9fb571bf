"""Collections of meshes on a ``dask.distributed`` cluster: one task per mesh.

:func:`map_files` runs what :func:`subdiv.batch` runs — ``info``, ``interpolate`` or
``subdivide`` with the options of the single command — with one task per input file on the
cluster's workers, and gathers one record per input (a ``dict``: ``input``, ``outputs``,
``report`` or ``error``, ``skipped``, ``seconds``, ``index``, ``name``, ``warnings``), in input
order. A record is the one :func:`subdiv.batch` (and ``subdiv batch`` on the command line)
makes for the same input, but for the timings; a failing mesh is a record with an ``error``
and never stops the others; outputs already complete are skipped (``resume``).

The workers read the inputs and write into ``out_dir`` themselves: on a multi-machine
cluster both must be paths every worker sees (a shared file system), and ``subdiv`` must be
installed on every worker::

    from dask.distributed import Client
    import subdiv.dask
    client = Client("tcp://scheduler:8786")
    records = subdiv.dask.map_files("/data/scans/*.obj", "/data/out", "interpolate",
                                    client=client, method="cheng", levels=2)
    failed = [r for r in records if r["error"]]

Ray users can call :func:`subdiv.batch` on each shard of their file list in a Ray task: no
code of ours is needed for that.
"""

import json
import os
from typing import Any, Iterable, List, Optional, Union

from . import _subdiv

__all__ = ["map_files"]

PathLike = Union[str, "os.PathLike[str]"]


def _run_one(
    index: int, path: str, name: str, out_dir: str, command: str, options_json: str, resume: bool
) -> "dict[str, Any]":
    """The task: one input of the batch, on a worker."""
    return json.loads(_subdiv.run_one(index, path, name, out_dir, command, options_json, resume))


def map_files(
    paths: Union[PathLike, Iterable[PathLike]],
    out_dir: PathLike,
    command: str,
    client: Optional[Any] = None,
    *,
    resume: bool = True,
    **options: Any,
) -> "List[dict[str, Any]]":
    """Run ``command`` over ``paths`` on a ``dask.distributed`` cluster, one task per mesh.

    Args:
        paths: files, directories (the mesh files in them) and glob patterns, as for
            :func:`subdiv.batch`; expanded here, on the client.
        out_dir: where the outputs and ``NAME.record.json`` files go (created by the workers).
        command: ``"info"``, ``"interpolate"`` or ``"subdivide"``.
        client: a ``dask.distributed.Client``; ``None``: the current default client.
        resume: skip inputs whose stored record says they are done.
        **options: the command's options, as for :func:`subdiv.batch` (checked here, before
            any task is submitted: a misspelled option raises ``ValueError``).

    Returns:
        One record per input, in input order.
    """
    from distributed import default_client

    given = [paths] if isinstance(paths, (str, os.PathLike)) else list(paths)
    files, names = _subdiv.expand_inputs([os.fspath(p) for p in given])
    options_json = json.dumps(options)
    _subdiv.check_command(command, options_json)
    client = client if client is not None else default_client()
    n = len(files)
    futures = client.map(
        _run_one,
        range(n),
        [os.fspath(f) for f in files],
        names,
        [os.fspath(out_dir)] * n,
        [command] * n,
        [options_json] * n,
        [resume] * n,
        pure=False,
    )
    return client.gather(futures)
