// tests/integrators/batch_control_contracted.cpp — the AVX2 lane blocks with FMA contraction (tests/CMakeLists.txt:
// -O3 -mavx2 -mfma -ffp-contract=fast): a negative control of test_batch (batch_kernel_controls.hpp).
#define LGI_BATCH_ISA avx2_contracted
#include "batch_control_kernels.inc"
