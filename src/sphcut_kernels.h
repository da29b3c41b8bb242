/* -*- c++ -*- ----------------------------------------------------------
   sphcut - SPH smoothing kernels (host and device).

   All kernels have compact support of radius 2h (q = r/h in [0,2)), so the
   LAMMPS pair cutoff is 2h.  W(r,h) = sigma_d / h^d * f(q).
     CUBIC      cubic B-spline (Monaghan & Lattanzio 1985), used by seed 003
     WENDLAND   Wendland C2 (Wendland 1995; Dehnen & Aly 2012 scaling)
     HYPERBOLIC hyperbolic spline of Yang, Liu & Peng (2014), used by seed 000:
                f = q^3 - 6q + 6 (q<1), (2-q)^3 (1<=q<2); its gradient does not
                vanish at q -> 0, which removes the pairing instability.
   Normalisations (checked by unittest/test_kernels.cpp):
     cubic      2D 10/(7 pi)   3D 1/pi
     wendland   2D 7/(4 pi)    3D 21/(16 pi)   (f = (1-q/2)^4 (2q+1))
     hyperbolic 2D 1/(3 pi)    3D 15/(62 pi)
------------------------------------------------------------------------- */

#ifndef SPHCUT_KERNELS_H
#define SPHCUT_KERNELS_H

#include "sphcut_math.h"

namespace sphcut {

enum KernelKind { KERNEL_CUBIC = 0, KERNEL_WENDLAND = 1, KERNEL_HYPERBOLIC = 2 };

// the support of every kernel: W = 0 from q = r/h = KERNEL_SUPPORT_Q on
constexpr double KERNEL_SUPPORT_Q = 2.0;

// the support radius 2h of smoothing length h (the pair cutoff; neighbours beyond it carry nothing)
SPHCUT_INLINE double support_radius(double h)
{
  return KERNEL_SUPPORT_Q * h;
}

// its square (2h)^2, what the neighbour loops compare r^2 with
SPHCUT_INLINE double support_radius_sq(double h)
{
  const double rc = support_radius(h);
  return rc * rc;
}

SPHCUT_INLINE double kernel_sigma(int kind, int dim)
{
  const double pi = 3.14159265358979323846;
  if (kind == KERNEL_WENDLAND) return dim == 2 ? 7.0 / (4.0 * pi) : 21.0 / (16.0 * pi);
  if (kind == KERNEL_HYPERBOLIC) return dim == 2 ? 1.0 / (3.0 * pi) : 15.0 / (62.0 * pi);
  return dim == 2 ? 10.0 / (7.0 * pi) : 1.0 / pi;
}

// shape function f(q) and its derivative df/dq
SPHCUT_INLINE void kernel_shape(int kind, double q, double &f, double &df)
{
  f = 0.0;
  df = 0.0;
  if (q >= KERNEL_SUPPORT_Q) return;
  if (kind == KERNEL_WENDLAND) {
    const double t = 1.0 - 0.5 * q;
    const double t3 = t * t * t;
    f = t3 * t * (2.0 * q + 1.0);
    df = -5.0 * q * t3;    // d/dq[(1-q/2)^4 (2q+1)] = -5 q (1-q/2)^3
  } else {
    // both pieces, then a select: no branch on q < 1, which a neighbour list takes in no
    // predictable order
    const double t = 2.0 - q;
    const bool inner = q < 1.0;
    if (kind == KERNEL_HYPERBOLIC) {
      const double fi = q * q * q - 6.0 * q + 6.0, dfi = 3.0 * q * q - 6.0;
      const double fo = t * t * t, dfo = -3.0 * t * t;
      f = inner ? fi : fo;
      df = inner ? dfi : dfo;
    } else {
      const double fi = 1.0 - 1.5 * q * q + 0.75 * q * q * q, dfi = -3.0 * q + 2.25 * q * q;
      const double fo = 0.25 * t * t * t, dfo = -0.75 * t * t;
      f = inner ? fi : fo;
      df = inner ? dfi : dfo;
    }
  }
}

// x_i - x_j and its square; false beyond the support 2h or for coincident particles
SPHCUT_INLINE bool in_support(const double *xi, const double *xj, double h, double *dx, double &r2)
{
  r2 = 0.0;
  for (int a = 0; a < 3; a++) {
    dx[a] = xi[a] - xj[a];
    r2 += dx[a] * dx[a];
  }
  return r2 < support_radius_sq(h) && r2 != 0.0;
}

// W(r, h)
SPHCUT_INLINE double kernel_w(int kind, int dim, double r, double h)
{
  double f, df;
  kernel_shape(kind, r / h, f, df);
  const double hd = dim == 2 ? h * h : h * h * h;
  return kernel_sigma(kind, dim) / hd * f;
}

// W and (1/r) dW/dr, so that grad_i W_ij = wfac * (x_i - x_j)
SPHCUT_INLINE void kernel_w_gradfac(int kind, int dim, double r, double h, double &w, double &wfac)
{
  double f, df;
  kernel_shape(kind, r / h, f, df);
  const double hd = dim == 2 ? h * h : h * h * h;
  const double s = kernel_sigma(kind, dim) / hd;
  w = s * f;
  wfac = r > 0.0 ? s * df / (h * r) : 0.0;
}

// the same with the type-pair constants precomputed (inv_h = 1/h, wnorm = sigma_d/h^d):
// one division per pair instead of three
SPHCUT_INLINE void kernel_w_gradfac_pre(int kind, double r, double inv_h, double wnorm, double &w, double &wfac)
{
  double f, df;
  kernel_shape(kind, r * inv_h, f, df);
  w = wnorm * f;
  wfac = r > 0.0 ? wnorm * df * inv_h / r : 0.0;
}

}    // namespace sphcut

#endif
