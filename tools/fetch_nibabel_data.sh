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

fetch_wheel_files fetch_nibabel_data nibabel 5.3.2 nibabel/tests/data "$DEST" "${FILES[@]}"
