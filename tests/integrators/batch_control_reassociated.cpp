// tests/integrators/batch_control_reassociated.cpp — the AVX2 lane blocks with reassociated sums (tests/CMakeLists.txt:
// -O3 -mavx2 -mfma -ffp-contract=off -fassociative-math -fno-signed-zeros -fno-trapping-math): a negative control
// of test_batch (batch_kernel_controls.hpp).
#define LGI_BATCH_ISA avx2_reassociated
#include "batch_control_kernels.inc"
