#!/bin/sh
# Render every case of a lightproof export with lightproof's own `render` (written by
# `lightproof export --to lightproof`): independent renders renders/000.exr ... (render k
# with seed k) in every case folder listed in cases.txt. Then: lightproof judge --suite DIR
# Settings: LIGHTPROOF (the binary, default lightproof), RENDERS (default 16), SPP (default 64).
set -eu
LIGHTPROOF=${LIGHTPROOF:-lightproof}
RENDERS=${RENDERS:-16}
SPP=${SPP:-64}
root=$(cd "$(dirname "$0")" && pwd)
while IFS= read -r id; do
  d="$root/$id"
  mkdir -p "$d/renders"
  rm -f "$d/renders/"*.exr
  k=0
  while [ "$k" -lt "$RENDERS" ]; do
    n=$(printf %03d "$k")
    # shellcheck disable=SC2046
    (cd "$d" && "$LIGHTPROOF" render scene.json --spp "$SPP" --seed "$k" -o "renders/$n.exr" $(cat render.args))
    k=$((k + 1))
  done
done < "$root/cases.txt"
