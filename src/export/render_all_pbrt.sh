#!/bin/sh
# Render every case of a lightproof export with pbrt-v4 (written by `lightproof export
# --to pbrt`): independent renders renders/000.exr ... (render k with `--seed k`) and
# renders/render.json in every case folder listed in cases.txt, removing earlier renders
# first. Then: lightproof judge --suite DIR
# Settings: PBRT (the binary, default pbrt), RENDERS (default 16), SAMPLES (paths per
# render, default 65536: spp = SAMPLES / pixels, rounded up, as the Mitsuba driver does),
# THREADS (pbrt's --nthreads; default pbrt's own choice), ONLY (only the case ids that
# contain this text).
set -eu
PBRT=${PBRT:-pbrt}
RENDERS=${RENDERS:-16}
SAMPLES=${SAMPLES:-65536}
THREADS=${THREADS:-}
ONLY=${ONLY:-}
root=$(cd "$(dirname "$0")" && pwd)
while IFS= read -r id; do
  case "$id" in *"$ONLY"*) ;; *) continue ;; esac
  d="$root/$id"
  w=$(sed -n 's/^ *"width": *\([0-9]*\).*/\1/p' "$d/export.json")
  h=$(sed -n 's/^ *"height": *\([0-9]*\).*/\1/p' "$d/export.json")
  spp=$(((SAMPLES + w * h - 1) / (w * h)))
  mkdir -p "$d/renders"
  rm -f "$d/renders/"*.exr "$d/renders/render.json"
  k=0
  while [ "$k" -lt "$RENDERS" ]; do
    n=$(printf %03d "$k")
    (cd "$d" && "$PBRT" --quiet ${THREADS:+--nthreads "$THREADS"} --seed "$k" --spp "$spp" \
      --outfile "renders/$n.exr" scene.pbrt)
    k=$((k + 1))
  done
  printf '{"renderer": "pbrt-v4", "spp": %s, "seeds": [0, %s]}\n' "$spp" "$((RENDERS - 1))" \
    > "$d/renders/render.json"
  echo "$id: $RENDERS renders x $spp spp"
done < "$root/cases.txt"
