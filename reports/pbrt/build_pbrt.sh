#!/bin/sh
# How pbrt-v4 was built for reports/pbrt (Debian 12, 2 cores, no GPU, no general
# internet: GitHub snapshots only). Run from a folder holding bare mirrors of the
# repositories below as MIRROR/<owner>+<name>/repo (e.g. from `git clone --mirror`).
# The pbrt snapshot lacked two large data files and one pinned submodule commit; see
# README.md here. Usage: MIRROR=/work/.mirror SRC=/work/pbrt-v4-src BUILD=/work/pbrt-build sh build_pbrt.sh
set -eu
MIRROR=${MIRROR:-/work/.mirror}
SRC=${SRC:-/work/pbrt-v4-src}
BUILD=${BUILD:-/work/pbrt-build}
here=$(cd "$(dirname "$0")" && pwd)
apt-get install -y cmake libopenexr-dev zlib1g-dev libgl-dev libx11-dev libxrandr-dev \
  libxinerama-dev libxcursor-dev libxi-dev libxext-dev
G="git --git-dir=$MIRROR/mmp+pbrt-v4/repo"
mkdir -p "$SRC"
# pbrt-v4 at 5f7a6068 without the two blobs the snapshot lacks
$G archive HEAD $($G ls-tree -r --name-only HEAD | grep -v -E 'util/bluenoise.cpp|util/pmj02tables.cpp') \
  | tar -x -C "$SRC"
python3 "$here/gen_missing_tables.py" "$SRC"
cd "$SRC/src/ext"
for s in ptex:wdas+ptex:054047d02b9e06e690420b407114d2872435b953 \
         double-conversion:mmp+double-conversion:cc1f75a114aca8d2af69f73a5a959aecbab0e87a \
         stb:nothings+stb:af1a5bc352164740c1cc1354942b1c6b72eacb8a \
         filesystem:wjakob+filesystem:c5f9de30142453eb3c6fe991e82dfc2583373116 \
         libdeflate:mmp+libdeflate:1fd0bea6ca2073c68493632dafc4b1ddda1bcbc3 \
         lodepng:lvandeve+lodepng:8c6a9e30576f07bf470ad6f09458a2dcd7a6a84a \
         utf8proc:JuliaStrings+utf8proc:d7bf128df773c2a1a7242eb80e51e91a769fc985 \
         qoi:phoboslab+qoi:028c75fd26e5e0758c7c711216c00404994c1ad3 \
         glfw:glfw+glfw:7b6aead9fb88b3623e3b3725ebb42670cbe4c579 \
         openvdb:AcademySoftwareFoundation+openvdb:414bed84c2fc22e188eac7b611aa85c7edd7a5a9; do
  d=${s%%:*}; rest=${s#*:}; m=${rest%%:*}; h=${rest#*:}
  rm -rf "$d"
  git clone -q --shared --no-checkout "$MIRROR/$m/repo" "$d"
  git -C "$d" -c advice.detachedHead=false checkout -q "$h" || true  # double-conversion: 2 test files absent, unused
done
# double-conversion's pinned 101e1ba is not in the snapshot (mmp's master cc1f75a is);
# OpenEXR and zlib come from Debian: skip their submodule checks.
cd "$SRC"
sed -i -e 's/^check_ext ("OpenEXR"/# check_ext ("OpenEXR"/' \
       -e 's/^check_ext ("zlib"/# check_ext ("zlib"/' \
       -e 's/^check_ext ("double-conversion"/# check_ext ("double-conversion"/' CMakeLists.txt
mkdir -p "$BUILD" && cd "$BUILD"
cmake -DCMAKE_BUILD_TYPE=Release -DGLFW_BUILD_WAYLAND=OFF -DBUILD_TESTING=OFF "$SRC"
time nice -n 10 make -j2 pbrt_exe
