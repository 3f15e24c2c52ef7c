// The lock-step kernel without AVX-512 (plain x86-64, or any other processor), which every
// processor runs: the tests compare it with the scalar search.
#define LOCKSTEP_ISA baseline
#include "lockstep_kernel.inc"
