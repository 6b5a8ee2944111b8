#!/usr/bin/env bash
# Builds scripts/pcl_tabletop.cpp against Debian's PCL (`apt-get install libpcl-dev`)
# and times PCL's organized and unorganized tabletop pipelines on PCD frames:
#   scripts/pcl_tabletop.sh REPS FRAME.pcd...
# The same frames for tabula: `tabula bench frames --cloud FRAME.pcd --reps REPS`.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="${TMPDIR:-/tmp}/pcl_tabletop"
if [ ! -x "$bin" ] || [ "$here/pcl_tabletop.cpp" -nt "$bin" ]; then
  g++ -O2 -std=c++17 -o "$bin" "$here/pcl_tabletop.cpp" \
    $(pkg-config --cflags --libs pcl_segmentation pcl_features pcl_filters \
      pcl_surface pcl_io pcl_search pcl_kdtree pcl_common) \
    -Wno-deprecated-declarations
fi
exec "$bin" "$@"
