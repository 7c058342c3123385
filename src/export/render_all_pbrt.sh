#!/bin/sh
# Render every case of a lightproof export with pbrt-v4 (written by `lightproof export
# --to pbrt`): independent renders renders/000.exr ... (render k with `--seed k`) in every
# case folder listed in cases.txt. Then: lightproof judge --suite DIR --renderer pbrt
# Settings: PBRT (the binary, default pbrt), RENDERS (default 16), SPP (samples per pixel,
# default 4096).
set -eu
PBRT=${PBRT:-pbrt}
RENDERS=${RENDERS:-16}
SPP=${SPP:-4096}
root=$(cd "$(dirname "$0")" && pwd)
while IFS= read -r id; do
  d="$root/$id"
  mkdir -p "$d/renders"
  rm -f "$d/renders/"*.exr
  k=0
  while [ "$k" -lt "$RENDERS" ]; do
    n=$(printf %03d "$k")
    (cd "$d" && "$PBRT" --quiet --seed "$k" --spp "$SPP" --outfile "renders/$n.exr" scene.pbrt)
    k=$((k + 1))
  done
done < "$root/cases.txt"
