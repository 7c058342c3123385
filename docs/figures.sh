#!/bin/sh
# Regenerates the figures README.md shows inline, committed under docs/:
#
#   sh docs/figures.sh
#
# 04_inverse_square.svg and 08_efficiency.svg come from the examples (which write them
# under target/examples/; 08's efficiencies use wall-clock times, so they move from run
# to run), pulsed_disk_transient.svg from `report` on the catalog's time-resolved
# histogram, blackbodies.png from `render` of a spectral scene. Look at an SVG with
# `rsvg-convert -o x.png docs/NAME.svg` (Debian: librsvg2-bin).
set -eu
cargo run --release --quiet --example 04_irradiance > /dev/null
cargo run --release --quiet --example 08_importance_sampling > /dev/null
cp target/examples/04_inverse_square.svg target/examples/08_efficiency.svg docs/
cargo run --release --quiet -- report analytic/cases/time/pulsed_disk_transient.json \
    --out target/figures --estimator light --sampler sobol --max-samples 1048576 --fresh > /dev/null
cp target/figures/pulsed_disk_transient.transient.svg docs/pulsed_disk_transient.svg
cargo run --release --quiet -- render analytic/scenes/blackbodies.json --spp 256 -o docs/blackbodies.png
echo "wrote docs/04_inverse_square.svg docs/08_efficiency.svg docs/pulsed_disk_transient.svg docs/blackbodies.png"
