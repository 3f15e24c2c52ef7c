// The lock-step kernel for the x86-64 baseline (SSE2), which every processor runs.
#define LOCKSTEP_ISA baseline
#include "lockstep_kernel.inc"
