#!/bin/sh
# The OpenBLAS kernels (OPENBLAS_CORETYPE) that this x86-64 CPU can execute, among the
# ones `make test-kernels` runs: Prescott (SSE3) and Nehalem (SSE4.2) on any x86-64 CPU
# of the last 15 years, Sandybridge where it has AVX, Zen where it has AVX2 and FMA.
# An AVX-512 kernel (SkylakeX) is left out: it crashes where the CPU lacks it.
flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null)
has() { case " $flags " in *" $1 "*) return 0;; esac; return 1; }
out=""
has pni && out="$out Prescott"
has sse4_2 && out="$out Nehalem"
has avx && out="$out Sandybridge"
has avx2 && has fma && out="$out Zen"
echo $out
