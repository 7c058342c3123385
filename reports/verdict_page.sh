#!/bin/sh
# The verdict page of a small run, looked at in a real headless browser.
#
#   sh reports/verdict_page.sh [OUT]      (default OUT: target/verdict-page)
#
# Runs `lightproof verify --html` on the irradiance catalog plus one copy of
# `disk_on_axis` whose reference is scaled by 1.01 (a 1% bias planted on purpose, so the
# page shows a failure, its row first and its z in the histogram's tail), then
# screenshots the page with Chromium (Debian: `apt-get install chromium`) to
# OUT/verdicts.png. The verify run exits 1 because of the planted failure; that is
# expected. Needs no network: the page is self-contained. LIGHTPROOF_BIN names a
# binary already built (default: `cargo run --release --quiet --`).
set -eu
out=${1:-target/verdict-page}
rm -rf "$out/cases"
mkdir -p "$out/cases"
cp analytic/cases/irradiance/*.json "$out/cases/"
sed -e 's/"reference": {/"reference": { "scale": 1.01,/' \
    -e 's/"name": "disk light on axis"/"name": "disk light on axis, reference planted 1% high"/' \
    analytic/cases/irradiance/disk_on_axis.json > "$out/cases/planted_bias.json"
${LIGHTPROOF_BIN:-cargo run --release --quiet --} verify "$out/cases" --html "$out/verdicts.html" > "$out/verify.txt" || true
tail -n 1 "$out/verify.txt"
dir=$(cd "$out" && pwd)
chromium --headless --no-sandbox --disable-gpu --hide-scrollbars \
    --screenshot="$dir/verdicts.png" --window-size=1400,2000 \
    "file://$dir/verdicts.html" 2>/dev/null
echo "wrote $out/verdicts.html and $out/verdicts.png"
# The table sorts in the browser: click the z header once, the smallest z comes first.
sed 's|</body>|<script>document.querySelectorAll("#verdict-table th")[5].click();</script></body>|' \
    "$dir/verdicts.html" > "$dir/sorted.html"
chromium --headless --no-sandbox --disable-gpu --dump-dom "file://$dir/sorted.html" 2>/dev/null |
    grep -o 'data-v="[-+0-9.e]*">[-+][0-9.]*</td><td class="n" data-v="[^"]*">[0-9.]*%' |
    head -n 3 | sed 's/.*">\([-+][0-9.]*\)<.*/after sorting by z, first rows have z = \1/'
