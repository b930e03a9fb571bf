from typing import Any, Optional

import subdiv

def from_usd_mesh(prim: Any, time: Optional[Any] = None) -> subdiv.Mesh:
    """The subdiv.Mesh of a UsdGeom.Mesh prim: composed values at ``time``, with its tags,
    options and primvars:st (needs usd-core)."""

def to_usd_mesh(mesh: subdiv.Mesh, stage: Any, path: str, scheme: str = "catmullClark") -> Any:
    """Writes ``mesh`` as a UsdGeom.Mesh at ``path`` of ``stage``'s edit target, with
    subdivisionScheme ``scheme``; returns the UsdGeom.Mesh (needs usd-core)."""
