#!/bin/bash
# Build the compiled tree: a copy of src/ in /tmp/cy-build/src with the extensions in place.
set -e
. /tmp/cyvenv/bin/activate
rm -rf /tmp/cy-build && mkdir -p /tmp/cy-build && cp -r /work/wt-cy/src /tmp/cy-build/
cd /tmp/cy-build/src
export CY_OPTS="${CY_OPTS} -X annotation_typing=False"
MODS="motionvm/drives/mechanics.py motionvm/drives/cia402.py motionvm/motion/profile.py motionvm/motion/axis_cycle.py $EXTRA_MODS"
export CFLAGS="-O2 -ffp-contract=off"
time cythonize -3 -i -q -j 2 ${CY_OPTS} $MODS 2>&1 | grep -v "^gcc\|^creating\|^copying\|running build_ext\|^building" || true
ls motionvm/*/*.so
