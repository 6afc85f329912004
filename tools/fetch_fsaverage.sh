#!/usr/bin/env bash
# Fetch the left hemisphere of FreeSurfer's fsaverage5 (10242 vertices) into
# data/fsaverage/ at the repository root: the pial, white and inflated surfaces
# and the sulcal depth and curvature per vertex, as GIfTI files.
#
# They come from the nilearn wheel on PyPI (version 0.14.1), which holds them
# gzipped under nilearn/datasets/data/fsaverage5/; they are unpacked and
# decompressed (pial_left.gii.gz becomes pial_left.gii). The bundled
# meshes/fsaverage5_pial_left.obj came from the same pial surface.
# data/ is git-ignored: the files are never committed.
#
# Usage: tools/fetch_fsaverage.sh
# Running it again does nothing when every file is already there.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readonly DEST="$repo_root/data/fsaverage"
# shellcheck source=tools/wheel_data.sh
source "$repo_root/tools/wheel_data.sh"
readonly FILES=(
    pial_left.gii
    white_left.gii
    infl_left.gii
    sulc_left.gii
    curv_left.gii
)

if all_files_present "$DEST" "${FILES[@]}"; then
    echo "fetch_fsaverage: all ${#FILES[@]} files are already in $DEST; nothing to do"
    exit 0
fi
command -v gzip >/dev/null || {
    echo "fetch_fsaverage: error: gzip is not installed" >&2
    exit 1
}

members=()
for file in "${FILES[@]}"; do
    members+=("nilearn/datasets/data/fsaverage5/$file.gz" "$DEST/$file.gz")
done
unpack_from_wheel fetch_fsaverage nilearn 0.14.1 "${members[@]}"
for file in "${FILES[@]}"; do
    gzip -dc "$DEST/$file.gz" >"$DEST/$file.part"
    mv "$DEST/$file.part" "$DEST/$file"
    rm "$DEST/$file.gz"
done
all_files_present "$DEST" "${FILES[@]}" || {
    echo "fetch_fsaverage: error: some files are empty after decompressing" >&2
    exit 1
}
echo "fetch_fsaverage: ${#FILES[@]} files written to $DEST"
