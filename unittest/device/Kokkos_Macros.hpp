// stand-in for Kokkos' macro header in the device-compile check (device_headers.cu): the
// shared physics functions as host + device functions, as a CUDA build of Kokkos declares them
#define KOKKOS_INLINE_FUNCTION __host__ __device__ inline
