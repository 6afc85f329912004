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

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readonly DEST="$repo_root/data/nibabel"
# shellcheck source=tools/wheel_data.sh
source "$repo_root/tools/wheel_data.sh"
readonly FILES=(
    anatomical.nii
    example4d.nii.gz
    example_nifti2.nii.gz
    functional.nii
    reoriented_anat_moved.nii
    resampled_anat_moved.nii
    standard.nii.gz
)

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

members=()
for file in "${FILES[@]}"; do
    members+=("nibabel/tests/data/$file" "$DEST/$file")
done
unpack_from_wheel fetch_nibabel_data nibabel 5.3.2 "${members[@]}"
all_present || {
    echo "fetch_nibabel_data: error: some files are empty after unpacking" >&2
    exit 1
}
echo "fetch_nibabel_data: ${#FILES[@]} files written to $DEST"
