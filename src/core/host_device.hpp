// SPDX-License-Identifier: GPL-3.0-or-later
// Marks physics kernels so that they compile for both host and CUDA device code.
#pragma once

#if defined(__CUDACC__)
#define GF_HOST_DEVICE __host__ __device__
#else
#define GF_HOST_DEVICE
#endif
