# SPDX-License-Identifier: GPL-3.0-or-later
#------------------------------------------------------------------------------
# Shell functions of the benches that run a solver serially and with the
# grains decomposed over NP ranks, each process under peakMemory.py (CPU
# time and peak RSS as GNU time -v reports them, and the sampled peaks of
# PSS and of the anonymous memory): tests/bench/granularCollapseDecomposed
# and tests/bench/rayleighTaylorDecomposed.  Source it; not a script.
#------------------------------------------------------------------------------

peakMemory=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/peakMemory.py

# time_serial SOLVER: run SOLVER in the current case directory, its record
# in time.serial.json, the log in log.SOLVER
time_serial() {
    python3 "$peakMemory" time.serial.json "$1" > "log.$1" 2>&1
}

# time_parallel SOLVER NP "SPLIT": decompose the current case (SPLIT: the
# decomposeParDict's method entries) and run SOLVER on NP ranks, each rank's
# record in time.rank<N>.json, the log in log.SOLVER
time_parallel() {
    local solver=$1 np=$2 split=$3
    cat > system/decomposeParDict <<DICT
FoamFile { version 2.0; format ascii; class dictionary; object decomposeParDict; }
numberOfSubdomains $np;
$split
DICT
    decomposePar -force > log.decomposePar 2>&1
    mpirun -np "$np" --oversubscribe sh -c \
        "python3 $peakMemory time.rank\$OMPI_COMM_WORLD_RANK.json $solver -parallel" \
        > "log.$solver" 2>&1
}
