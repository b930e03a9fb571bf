#!/usr/bin/env python3
"""Builds the installable Blender extension: a zip of blender/subdiv_interpolate with the
package's abi3 wheel inside.

    python blender/build_extension.py            # → target/blender-extension/subdiv_interpolate-VERSION-PLATFORM.zip
    python blender/build_extension.py --check    # and install it into a throw-away Blender (bpy)

Steps:
1. the wheel of crates/python (`maturin build --release`, or `pip wheel` when maturin is not
   installed), in the release profile of CARGO_TARGET_DIR (default target/), so the libraries
   built for the tests are reused;
2. a staged copy of the extension in target/blender-extension/subdiv_interpolate/ with the
   wheel in wheels/ and the manifest's `wheels` and `platforms` written from the wheel's name
   (the committed manifest has neither: nothing generated is committed);
3. the zip, manifest at its root (what `blender --command extension build` makes), validated
   with Blender's own `blender_ext.py validate` when the `bpy` module is importable;
4. with --check: `extension install-file` into a temporary Blender user directory, in a
   subprocess (`bpy` from PyPI), then the operator on a cube.

Install the zip: Edit ▸ Preferences ▸ Get Extensions ▸ Install from Disk, or
`blender --command extension install-file -r user_default -e ZIP`.
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
import zipfile
from importlib import util
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SOURCE = REPO / "blender" / "subdiv_interpolate"
PACKAGE = REPO / "crates" / "python"
EXTENSION_FILES = ("__init__.py", "blender_manifest.toml")

# A wheel's platform tag → Blender's platform name (blender_manifest.toml `platforms`): the
# system from the tag's start, the architecture from its end.
SYSTEMS = (("manylinux", "linux"), ("musllinux", "linux"), ("linux", "linux"), ("macosx", "macos"), ("win", "windows"))
ARCHITECTURES = (("x86_64", "x64"), ("amd64", "x64"), ("aarch64", "arm64"), ("arm64", "arm64"))


def target_dir() -> Path:
    return Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target")).resolve()


def build_wheel(out: Path) -> Path:
    """The abi3 wheel of crates/python, built into `out` (emptied first)."""
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    env = dict(os.environ, CARGO_TARGET_DIR=str(target_dir()))
    if shutil.which("maturin") or util.find_spec("maturin"):
        maturin = [shutil.which("maturin")] if shutil.which("maturin") else [sys.executable, "-m", "maturin"]
        command = maturin + ["build", "--release", "-m", str(PACKAGE / "Cargo.toml"), "--out", str(out)]
    else:
        command = [sys.executable, "-m", "pip", "wheel", "--no-deps", "-w", str(out), str(PACKAGE)]
    print("+", " ".join(command), flush=True)
    subprocess.run(command, check=True, env=env)
    wheels = sorted(out.glob("subdiv-*.whl"))
    if len(wheels) != 1:
        sys.exit(f"expected one subdiv wheel in {out}, found {[w.name for w in wheels]}")
    return wheels[0]


def blender_platform(wheel: Path) -> str:
    """Blender's platform name of a wheel, from its platform tag
    (subdiv-0.1.0-cp39-abi3-manylinux_2_35_x86_64.whl → linux-x64)."""
    tag = wheel.stem.split("-")[-1]
    system = next((name for start, name in SYSTEMS if tag.startswith(start)), None)
    arch = next((name for end, name in ARCHITECTURES if tag.endswith(end)), None)
    if system is None or arch is None:
        sys.exit(f"no Blender platform for the wheel tag {tag!r}")
    return f"{system}-{arch}"


def manifest_value(manifest: str, key: str) -> str:
    """A top-level string value of the manifest (`version = "0.1.0"` → 0.1.0)."""
    for line in manifest.splitlines():
        name, _, value = line.partition("=")
        if name.strip() == key:
            return value.strip().strip('"')
    sys.exit(f"blender_manifest.toml has no {key}")


def stage(wheel: Path, staged: Path) -> Path:
    """The extension's files with the wheel and the manifest's wheels/platforms, in `staged`."""
    shutil.rmtree(staged, ignore_errors=True)
    (staged / "wheels").mkdir(parents=True)
    for name in EXTENSION_FILES:
        shutil.copy2(SOURCE / name, staged / name)
    shutil.copy2(wheel, staged / "wheels" / wheel.name)
    manifest = (staged / "blender_manifest.toml").read_text()
    manifest += textwrap.dedent(
        f"""
        # Written by blender/build_extension.py for the bundled wheel.
        platforms = ["{blender_platform(wheel)}"]
        wheels = ["./wheels/{wheel.name}"]
        """
    )
    (staged / "blender_manifest.toml").write_text(manifest)
    return staged


def make_zip(staged: Path, zip_path: Path) -> Path:
    """The files of `staged` at the zip's root, in a fixed order."""
    zip_path.unlink(missing_ok=True)
    with zipfile.ZipFile(zip_path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for path in sorted(p for p in staged.rglob("*") if p.is_file() and "__pycache__" not in p.parts):
            archive.write(path, path.relative_to(staged).as_posix())
    return zip_path


def blender_ext() -> "Path | None":
    """Blender's extension command line (blender_ext.py) inside the `bpy` module, if installed."""
    spec = util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        return None
    found = sorted(Path(next(iter(spec.submodule_search_locations))).glob("*/scripts/addons_core/bl_pkg/cli/blender_ext.py"))
    return found[-1] if found else None


CHECK = """
import sys, pathlib, bpy  # first: addon_utils is importable once bpy is
import addon_utils
zip_path = sys.argv[-1]
bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
module = "bl_ext.user_default.subdiv_interpolate"
assert addon_utils.check(module)[1], module + " is not enabled"
site = pathlib.Path(bpy.utils.user_resource("EXTENSIONS", path=".local"))
wheels = sorted(p.name for p in site.rglob("subdiv/_subdiv*"))
assert wheels, "the bundled wheel was not installed under " + str(site)
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
bpy.ops.mesh.primitive_monkey_add()
assert bpy.ops.object.subdiv_interpolate() == {"FINISHED"}
print("installed, enabled and ran; the wheel's module:", wheels[0], "under", site)
"""


def check(zip_path: Path) -> None:
    """Installs the zip into a temporary Blender user directory and runs the operator."""
    with tempfile.TemporaryDirectory() as home:
        env = dict(os.environ, BLENDER_USER_RESOURCES=home)
        subprocess.run([sys.executable, "-c", CHECK, str(zip_path)], check=True, env=env)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=target_dir() / "blender-extension", help="output directory")
    parser.add_argument("--wheel", type=Path, help="use this wheel instead of building one")
    parser.add_argument("--check", action="store_true", help="install the zip into a temporary Blender (bpy) and run it")
    args = parser.parse_args()
    out = args.out.resolve()
    wheel = args.wheel.resolve() if args.wheel else build_wheel(out / "wheel")
    manifest = (SOURCE / "blender_manifest.toml").read_text()
    staged = stage(wheel, out / manifest_value(manifest, "id"))
    name = f"{manifest_value(manifest, 'id')}-{manifest_value(manifest, 'version')}-{blender_platform(wheel)}.zip"
    zip_path = make_zip(staged, out / name)
    validator = blender_ext()
    if validator is not None:
        subprocess.run([sys.executable, str(validator), "validate", str(zip_path)], check=True)
    else:
        print("bpy is not installed: the zip was not validated by Blender's blender_ext.py")
    if args.check:
        check(zip_path)
    print(zip_path)


if __name__ == "__main__":
    main()
