#!/bin/bash
# usage: icount.sh SRC N  -> instructions per axis-cycle (cachegrind, secs 0.3 - 0.1)
src=$1; n=$2
cd /work/wt-cy
ir() { PYTHONPATH=$src valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null python proto/icount.py $n $1 2>&1 | grep "I *refs" | awk '{gsub(",","",$NF); print $NF}'; }
a=$(ir 0.1); b=$(ir 0.3)
python3 -c "print('$src n=$n instr/axis-cycle', ($b-$a)/(200*$n))"
