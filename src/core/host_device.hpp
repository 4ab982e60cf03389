// SPDX-License-Identifier: GPL-3.0-or-later
// Marks physics kernels so that they compile for both host and CUDA device code.
#pragma once

#if defined(__CUDACC__)
#define GF_HOST_DEVICE __host__ __device__
#else
#define GF_HOST_DEVICE
#endif

/// For kernels that must be inlined into the loops that call them, so that a loop over contacts
/// can be vectorised as a whole (a call in its body stops the vectoriser).
#if defined(__CUDACC__)
#define GF_HOST_DEVICE_INLINE __host__ __device__ __forceinline__
#elif defined(__GNUC__)
#define GF_HOST_DEVICE_INLINE [[gnu::always_inline]] inline
#else
#define GF_HOST_DEVICE_INLINE inline
#endif
