/* -*- c++ -*- ----------------------------------------------------------
   sphcut - SPH metal cutting for LAMMPS

   Small fixed-size linear algebra used by the physics kernels.  Every
   function is SPHCUT_INLINE: plain inline on the host, and
   KOKKOS_INLINE_FUNCTION (host + device) when the Kokkos headers are in
   use, so the CPU styles and their /kk variants run the same arithmetic.

   Symmetric tensors are stored as 6 doubles in Voigt order
   (xx, yy, zz, xy, xz, yz); general 3x3 tensors as 9 doubles, row major
   (t[3*a+b] = T_ab).
------------------------------------------------------------------------- */

#ifndef SPHCUT_MATH_H
#define SPHCUT_MATH_H

#include <cmath>

#if defined(LMP_KOKKOS) || defined(SPHCUT_USE_KOKKOS_MACROS)
#include <Kokkos_Macros.hpp>
#define SPHCUT_INLINE KOKKOS_INLINE_FUNCTION
#else
#define SPHCUT_INLINE inline
#endif

// a function inlined into the neighbour loops whatever the compiler's size heuristics: GCC -O3
// called pair_terms out of line in the CPU pair's loop (15 % slower) and the heat fix's
// conduction_particle out of line in the /kk kernel (25 % more instructions), measured; host
// compilers only
#if defined(__GNUC__) && !defined(__CUDACC__)
#define SPHCUT_LOOP_INLINE SPHCUT_INLINE __attribute__((always_inline))
#else
#define SPHCUT_LOOP_INLINE SPHCUT_INLINE
#endif

namespace sphcut {

/* two adjacent doubles from a 16-byte aligned address: on a GPU one 128-bit load through the
   read-only path (the neighbour passes' rows, sphcut_pair.h PackedRow: half the load
   instructions of scalar loads, and the L1 cost of an irregular load is per instruction);
   on the host two plain loads.  The same values either way.                               */
SPHCUT_INLINE void load2(const double *p, double &a, double &b)
{
#if defined(__CUDA_ARCH__)
  const double2 v = __ldg(reinterpret_cast<const double2 *>(p));
  a = v.x;
  b = v.y;
#else
  a = p[0];
  b = p[1];
#endif
}

enum Voigt { XX = 0, YY = 1, ZZ = 2, XY = 3, XZ = 4, YZ = 5 };

SPHCUT_INLINE double sq(double x) { return x * x; }

// symmetric tensor (Voigt) contraction s:s
SPHCUT_INLINE double sym_ddot(const double *s)
{
  return s[XX] * s[XX] + s[YY] * s[YY] + s[ZZ] * s[ZZ] +
      2.0 * (s[XY] * s[XY] + s[XZ] * s[XZ] + s[YZ] * s[YZ]);
}

// von Mises equivalent of a deviatoric tensor: sqrt(3/2 s:s)
SPHCUT_INLINE double von_mises(const double *s)
{
  return sqrt(1.5 * sym_ddot(s));
}

// remove the trace: s <- s - tr(s)/3 I, returns tr(s)/3
SPHCUT_INLINE double deviator(double *s)
{
  const double m = (s[XX] + s[YY] + s[ZZ]) / 3.0;
  s[XX] -= m;
  s[YY] -= m;
  s[ZZ] -= m;
  return m;
}

// c = a * b (general 3x3)
SPHCUT_INLINE void mat_mul(const double *a, const double *b, double *c)
{
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      c[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}

// inverse of a general 3x3 matrix; in 2D (dim == 2) only the x-y block is
// inverted and the zz entry is set to 1.  Returns the determinant; on a
// (near) singular matrix the identity is returned with determinant 0.
SPHCUT_INLINE double mat_inverse(const double *a, double *inv, int dim)
{
  for (int k = 0; k < 9; k++) inv[k] = 0.0;
  if (dim == 2) {
    const double det = a[0] * a[4] - a[1] * a[3];
    const double scale = fabs(a[0]) + fabs(a[1]) + fabs(a[3]) + fabs(a[4]);
    if (!(fabs(det) > 1.0e-12 * scale * scale)) {
      inv[0] = inv[4] = inv[8] = 1.0;
      return 0.0;
    }
    inv[0] = a[4] / det;
    inv[1] = -a[1] / det;
    inv[3] = -a[3] / det;
    inv[4] = a[0] / det;
    inv[8] = 1.0;
    return det;
  }
  const double c00 = a[4] * a[8] - a[5] * a[7];
  const double c01 = a[5] * a[6] - a[3] * a[8];
  const double c02 = a[3] * a[7] - a[4] * a[6];
  const double det = a[0] * c00 + a[1] * c01 + a[2] * c02;
  double scale = 0.0;
  for (int k = 0; k < 9; k++) scale += fabs(a[k]);
  if (!(fabs(det) > 1.0e-12 * scale * scale * scale)) {
    inv[0] = inv[4] = inv[8] = 1.0;
    return 0.0;
  }
  const double id = 1.0 / det;
  inv[0] = c00 * id;
  inv[1] = (a[2] * a[7] - a[1] * a[8]) * id;
  inv[2] = (a[1] * a[5] - a[2] * a[4]) * id;
  inv[3] = c01 * id;
  inv[4] = (a[0] * a[8] - a[2] * a[6]) * id;
  inv[5] = (a[2] * a[3] - a[0] * a[5]) * id;
  inv[6] = c02 * id;
  inv[7] = (a[1] * a[6] - a[0] * a[7]) * id;
  inv[8] = (a[0] * a[4] - a[1] * a[3]) * id;
  return det;
}

// cyclic Jacobi rotations of a symmetric 3x3 tensor (Voigt) to diagonal form: eigenvalues in
// lam[3] and, with VEC, the eigenvectors as columns of q (row major).  Without VEC the
// rotations are the same, so lam is the same to the bit, without the work on the vectors.
template <bool VEC> SPHCUT_INLINE void sym_jacobi(const double *s, double *lam, double *q)
{
  double a[3][3] = {{s[XX], s[XY], s[XZ]}, {s[XY], s[YY], s[YZ]}, {s[XZ], s[YZ], s[ZZ]}};
  double v[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  for (int sweep = 0; sweep < 12; sweep++) {
    const double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
    const double diag = fabs(a[0][0]) + fabs(a[1][1]) + fabs(a[2][2]);
    if (off <= 1.0e-15 * diag || off == 0.0) break;
    for (int p = 0; p < 2; p++) {
      for (int r = p + 1; r < 3; r++) {
        if (a[p][r] == 0.0) continue;
        const double theta = (a[r][r] - a[p][p]) / (2.0 * a[p][r]);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
        const double c = 1.0 / sqrt(t * t + 1.0);
        const double sn = t * c;
        for (int k = 0; k < 3; k++) {
          const double akp = a[k][p], akr = a[k][r];
          a[k][p] = c * akp - sn * akr;
          a[k][r] = sn * akp + c * akr;
        }
        for (int k = 0; k < 3; k++) {
          const double apk = a[p][k], ark = a[r][k];
          a[p][k] = c * apk - sn * ark;
          a[r][k] = sn * apk + c * ark;
        }
        if (VEC)
          for (int k = 0; k < 3; k++) {
            const double vkp = v[k][p], vkr = v[k][r];
            v[k][p] = c * vkp - sn * vkr;
            v[k][r] = sn * vkp + c * vkr;
          }
      }
    }
  }
  for (int k = 0; k < 3; k++) {
    lam[k] = a[k][k];
    if (VEC)
      for (int l = 0; l < 3; l++) q[3 * k + l] = v[k][l];
  }
}

// eigen decomposition of a symmetric 3x3 tensor (Voigt) by cyclic Jacobi
// rotations: eigenvalues in lam[3], eigenvectors as columns of q (row major).
SPHCUT_INLINE void sym_eigen(const double *s, double *lam, double *q)
{
  sym_jacobi<true>(s, lam, q);
}

// the eigenvalues alone (the same values as sym_eigen's)
SPHCUT_INLINE void sym_eigenvalues(const double *s, double *lam)
{
  sym_jacobi<false>(s, lam, nullptr);
}

// eigen decomposition of the x-y block of a symmetric tensor (closed form);
// lam[2] = zz entry and q's third column = e_z.
SPHCUT_INLINE void sym_eigen_2d(const double *s, double *lam, double *q)
{
  const double m = 0.5 * (s[XX] + s[YY]);
  const double d = 0.5 * (s[XX] - s[YY]);
  const double r = sqrt(d * d + s[XY] * s[XY]);
  lam[0] = m + r;
  lam[1] = m - r;
  lam[2] = s[ZZ];
  const double phi = 0.5 * atan2(s[XY], d);
  const double c = cos(phi), sn = sin(phi);
  q[0] = c;  q[1] = -sn; q[2] = 0.0;
  q[3] = sn; q[4] = c;   q[5] = 0.0;
  q[6] = 0.0; q[7] = 0.0; q[8] = 1.0;
}

}    // namespace sphcut

#endif
