"""Conversion between subdiv meshes and Pixar USD's ``UsdGeom.Mesh`` prims (needs ``usd-core``).

``subdiv.read`` and ``subdiv.write`` take ``.usda``, ``.usdc`` and ``.usdz`` files by
themselves (a file of one Mesh prim; the command line handles files of several). This module
goes between an open ``pxr.Usd.Stage`` and :class:`subdiv.Mesh`, through subdiv's own USD
reader and writer: the prim's layer data is copied into a temporary one-prim layer that
``subdiv.read`` reads, and a written one-prim layer is copied onto the stage, so that both
directions map points, faces, orientation, creases, corners, holes, the subdivision options
and ``primvars:st`` exactly as the files do (``subdiv_io::usd``).

>>> from pxr import Usd                                   # doctest: +SKIP
>>> stage = Usd.Stage.Open("scene.usda")                  # doctest: +SKIP
>>> mesh = subdiv.usd.from_usd_mesh(stage.GetPrimAtPath("/World/Body"))  # doctest: +SKIP
>>> control = subdiv.interpolate(mesh, method="cheng").control            # doctest: +SKIP
>>> subdiv.usd.to_usd_mesh(control, stage, "/World/BodyCage")             # doctest: +SKIP
"""

import os
import tempfile
from typing import Any

import subdiv

_PRIM = "/Mesh"
"""Where subdiv's writer puts a single mesh (``subdiv_io::usd::DEFAULT_PRIM_PATH``)."""


def _pxr():
    try:
        from pxr import Sdf, Usd, UsdGeom
    except ImportError as e:  # pragma: no cover - exercised only without usd-core
        raise ImportError("subdiv.usd needs Pixar's USD Python package: pip install usd-core") from e
    return Sdf, Usd, UsdGeom


def from_usd_mesh(prim: Any, time: Any = None) -> "subdiv.Mesh":
    """The :class:`subdiv.Mesh` of a ``UsdGeom.Mesh`` prim (or a ``UsdGeom.Mesh`` schema object):
    its composed attribute values at ``time`` (default: the default time), with its tags,
    options and ``primvars:st``. Raises ``subdiv.InputError`` for an invalid mesh, ``ValueError``
    when the prim is not a Mesh."""
    Sdf, Usd, UsdGeom = _pxr()
    prim = prim.GetPrim() if hasattr(prim, "GetPrim") else prim
    if not prim or prim.GetTypeName() != "Mesh":
        raise ValueError(f"{prim}: not a UsdGeom.Mesh prim")
    layer = Sdf.Layer.CreateAnonymous(".usda")
    spec = Sdf.CreatePrimInLayer(layer, _PRIM)
    spec.specifier = Sdf.SpecifierDef
    spec.typeName = "Mesh"
    code = Usd.TimeCode.Default() if time is None else time
    # The composed values (references, variants, time samples resolved by pxr), one by one.
    for attribute in prim.GetAttributes():
        value = attribute.Get(code)
        if value is None:
            continue
        name = attribute.GetName()
        target = Sdf.AttributeSpec(spec, name, attribute.GetTypeName(), attribute.GetVariability())
        target.default = value
        interpolation = attribute.GetMetadata("interpolation")
        if interpolation:
            target.SetInfo("interpolation", interpolation)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "mesh.usda")
        layer.Export(path)
        return subdiv.read(path)


def to_usd_mesh(mesh: "subdiv.Mesh", stage: Any, path: str, scheme: str = "catmullClark") -> Any:
    """Writes ``mesh`` as a ``UsdGeom.Mesh`` at ``path`` of ``stage``'s edit target layer (the
    prim's previous opinions there replaced), with its tags, options and texture coordinates,
    and ``subdivisionScheme`` ``scheme`` (``catmullClark``, ``loop``, ``bilinear``, ``none``:
    ``none`` for refined surfaces). Returns the ``UsdGeom.Mesh``."""
    Sdf, _, UsdGeom = _pxr()
    if scheme not in ("catmullClark", "loop", "bilinear", "none"):
        raise ValueError(f"scheme {scheme!r}: catmullClark, loop, bilinear or none")
    with tempfile.TemporaryDirectory() as tmp:
        written = os.path.join(tmp, "mesh.usda")
        subdiv.write(mesh, written)
        source = Sdf.Layer.FindOrOpen(written)
        target = stage.GetEditTarget().GetLayer()
        Sdf.CreatePrimInLayer(target, path)
        if not Sdf.CopySpec(source, _PRIM, target, path):
            raise OSError(f"could not copy the mesh to {path}")
    usd_mesh = UsdGeom.Mesh(stage.GetPrimAtPath(path))
    usd_mesh.CreateSubdivisionSchemeAttr(scheme)
    return usd_mesh
