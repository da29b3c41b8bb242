# eigenvalues of the operator written by fmfs_lattice / fmfs_chip: the largest (0 for the
# constant mode; > 0: a growing mode) and minus the smallest (spectral radius), times h^2
# (k = rho cp = 1: in units of k/(rho cp h^2)); usage: operator_eig.py out.bin h
import sys, numpy as np
f = open(sys.argv[1], 'rb'); N = int(np.frombuffer(f.read(4), np.int32)[0])
A = np.frombuffer(f.read(8 * N * N), np.float64).reshape(N, N)
h = float(sys.argv[2])
w, v = np.linalg.eigh(A)
# growth: largest eigenvalue (0 = constant mode); spectral radius: -min
x = np.frombuffer(f.read(), np.float64).reshape(N, 3)
top = v[:, -1]
loc = np.argsort(-np.abs(top))[:3]
print("lam_max*h^2 %+.4e  (2nd %+.4e)  -lam_min*h^2 %.4f  top mode at %s" % (w[-1] * h * h, w[-2] * h * h, -w[0] * h * h,
      " ".join("(%.2f,%.2f)" % (x[i, 0], x[i, 1]) for i in loc)))
