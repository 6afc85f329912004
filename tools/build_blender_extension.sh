#!/usr/bin/env bash
# The Blender extension: blender/ with the crestline wheel bundled, packed as
# dist/crestline-<version>-blender-<platform>.zip.
#
#   tools/build_blender_extension.sh                 # builds the wheel (maturin, via pip)
#   tools/build_blender_extension.sh --wheel W.whl   # bundles a wheel built before
#
# The wheel is abi3: one wheel serves Blender's Python. The build uses
# CARGO_TARGET_DIR (default: the repository's target/), so a release build made
# before is reused. Where a `blender` binary is on the PATH, the zip is checked by
# `blender --command extension validate`. PYTHON (default python3) runs the wheel's build.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
cd "$ROOT"

wheel=""
if [[ "${1:-}" == "--wheel" ]]; then
    wheel="$(realpath "$2")"
elif [[ $# -gt 0 ]]; then
    echo "usage: $0 [--wheel FILE.whl]" >&2
    exit 2
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
if [[ -z "$wheel" ]]; then
    export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$ROOT/target}"
    "${PYTHON:-python3}" -m pip wheel --quiet --no-deps --wheel-dir "$work/built" ./crates/crestline-py
    wheel="$(ls "$work"/built/crestline-*.whl)"
fi

mkdir -p dist
python3 - "$wheel" "$work/extension" "$ROOT/dist" <<'PY'
"""Stage blender/ with the wheel, write the manifest's version, platform and
wheels, and zip it."""
import pathlib
import re
import shutil
import sys
import zipfile

wheel, stage, dist = map(pathlib.Path, sys.argv[1:])
# crestline-0.1.0-cp39-abi3-manylinux_2_34_x86_64.whl: name, version, tags.
_, version, _, _, platform_tag = wheel.stem.split("-", 4)
PLATFORMS = {
    r"manylinux.*_x86_64|linux_x86_64": "linux-x64",
    r"manylinux.*_aarch64|linux_aarch64": "linux-arm64",
    r"macosx_.*_arm64": "macos-arm64",
    r"macosx_.*_x86_64": "macos-x64",
    r"win_amd64": "windows-x64",
    r"win_arm64": "windows-arm64",
}
platform = next((name for pattern, name in PLATFORMS.items() if re.fullmatch(pattern, platform_tag)), None)
if platform is None:
    sys.exit(f"build_blender_extension: no Blender platform for the wheel's tag {platform_tag}")

source = pathlib.Path("blender")
shutil.copytree(source, stage, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "wheels"))
(stage / "wheels").mkdir()
shutil.copy(wheel, stage / "wheels" / wheel.name)
manifest = (stage / "blender_manifest.toml").read_text()
for key, value in (
    ("version", f'"{version}"'),
    ("platforms", f'["{platform}"]'),
    ("wheels", f'["./wheels/{wheel.name}"]'),
):
    manifest, n = re.subn(rf"(?m)^{key} = .*$", f"{key} = {value}", manifest)
    assert n == 1, key
(stage / "blender_manifest.toml").write_text(manifest)

out = dist / f"crestline-{version}-blender-{platform}.zip"
with zipfile.ZipFile(out.with_suffix(".zip.part"), "w", zipfile.ZIP_DEFLATED) as archive:
    for path in sorted(stage.rglob("*")):
        if path.is_file():
            archive.write(path, path.relative_to(stage))
out.with_suffix(".zip.part").replace(out)
print(out)
PY

if command -v blender >/dev/null; then
    blender --factory-startup --command extension validate "$(ls -t dist/crestline-*-blender-*.zip | head -1)"
fi
