#!/usr/bin/env bash
# Fetch the small NIfTI files that ship in nibabel's test data into data/nibabel/ at
# the repository root.
#
# They come from the nibabel wheel on PyPI (version 5.3.2), which holds them under
# nibabel/tests/data/. Only the NIfTI-1 and NIfTI-2 single files are unpacked.
# data/ is git-ignored: the files are never committed.
#
# Usage: tools/fetch_nibabel_data.sh
# Running it again does nothing when every file is already there.
set -euo pipefail

readonly VERSION="5.3.2"
readonly WHEEL="nibabel-$VERSION-py3-none-any.whl"

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readonly DEST="$repo_root/data/nibabel"
readonly FILES=(
    anatomical.nii
    example4d.nii.gz
    example_nifti2.nii.gz
    functional.nii
    reoriented_anat_moved.nii
    resampled_anat_moved.nii
    standard.nii.gz
)

die() {
    echo "fetch_nibabel_data: error: $*" >&2
    exit 1
}

all_present() {
    local file
    for file in "${FILES[@]}"; do
        [[ -s "$DEST/$file" ]] || return 1
    done
}

if all_present; then
    echo "fetch_nibabel_data: all ${#FILES[@]} files are already in $DEST; nothing to do"
    exit 0
fi

command -v python3 >/dev/null || die "python3 is not installed (its pip downloads the wheel)"
command -v unzip >/dev/null || die "unzip is not installed"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

echo "fetch_nibabel_data: downloading $WHEEL"
python3 -m pip download --quiet --no-deps --only-binary=:all: \
    --dest "$work" "nibabel==$VERSION" ||
    die "pip could not download nibabel $VERSION (is PyPI reachable?)"
[[ -s "$work/$WHEEL" ]] || die "pip left no $WHEEL in $work"

mkdir -p "$DEST"
for file in "${FILES[@]}"; do
    # Unpack to a temporary name first, so an interrupted run leaves no truncated
    # file behind that a later run would keep.
    unzip -p "$work/$WHEEL" "nibabel/tests/data/$file" >"$DEST/$file.part" ||
        die "$WHEEL holds no nibabel/tests/data/$file"
    mv "$DEST/$file.part" "$DEST/$file"
done

all_present || die "some files are empty after unpacking"
echo "fetch_nibabel_data: ${#FILES[@]} files written to $DEST"
