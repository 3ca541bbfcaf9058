#!/bin/bash
# usage: icount2.sh SRC N -> instructions per axis-cycle of the axis-only workload (1000 - 200 cycles)
src=$1; n=$2
cd /work/wt-cy
ir() { PYTHONPATH=$src valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null python proto/axisonly.py $n $1 2>&1 | grep "I *refs" | awk '{gsub(",","",$NF); print $NF}'; }
a=$(ir 200); b=$(ir 1000)
python3 -c "print('axis-only $src n=$n instr/axis-cycle', ($b-$a)/(800*$n))"
