// The lock-step kernel for AVX-512 (compiled with -mavx512f -mavx512dq: CMakeLists.txt), which
// LockstepTable calls only on a processor that has it.
#define LOCKSTEP_ISA avx512
#include "lockstep_kernel.inc"
