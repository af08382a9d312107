#!/usr/bin/python3
"""Independent reference implementation of 2D "KBM (si)" on the Timoshenko cantilever.

Purpose
-------
The 2D counterpart of tests/reference/kbm_1d.py: a self-contained
numpy/scipy implementation of the Krongauz-Belytschko-corrected
Petrov-Galerkin particle method with stress-point integration, "KBM (si)" of
Rabczuk, Belytschko & Xiao, CMAME 2004, "Stable particle methods based on
Lagrangian kernels" (called 001 below), applied to the cantilever of 001
sec. 9.1 (small strain, linear elastic, static).  Written from the paper
only; it shares no code with the C++ implementation under test.  Its job is
to tell whether the method as 001 writes it converges on the cantilever
and, if not, which ingredient stalls it (1D finding: (1) the Shepard test
gradients are not integrated consistently near the boundary, (2) the
stress-point rule violates the second-order divergence identity).

Problem (Timoshenko & Goodier, plane stress)
--------------------------------------------
Omega = [0, L] x [-D/2, D/2], L = 48, D = 12, E = 3e7, nu = 0.3, P = 1000,
I = D^3/12.
    u_x = -P y/(6EI) [(6L - 3x) x + (2 + nu)(y^2 - D^2/4)]
    u_y =  P/(6EI) [3 nu y^2 (L - x) + (4 + 5 nu) D^2 x/4 + (3L - x) x^2]
    s_xx = -P (L - x) y / I,  s_yy = 0,  s_xy = P/(2I) (D^2/4 - y^2)
x = L: traction t = sigma n = (0, P/(2I)(D^2/4 - y^2)); y = +-D/2: free
(sigma n = 0 exactly; the code loads every non-Dirichlet side with the exact
sigma n, which is zero there); x = 0: u = u_exact at the particles of that
side, both components, by Lagrange multipliers in Petrov-Galerkin form
    [ K        Phi_b^T ] [u]   [f]      constraint rows  sum_J Psi_J(x_b) u_J = g_b
    [ Psi_b    0       ] [l] = [g]      multiplier in test eq. I with Phi_I(x_b)
(trial = MLS Psi, test = Shepard Phi; kbm_1d.py shows why Phi_b is right).

Particles: square lattice, ny across the depth, nx = 4 (ny - 1) + 1 along the
length, particles on all four sides, spacing h = D/(ny - 1).

Ingredients (001 equation numbers)
----------------------------------
* Kernel: cubic spline eq (14), radial, z = r/h_k on [0, 2]; written with
  q = r/R, R = dmax*h the support radius (z = 2q); C/h^D of (14)-(15)
  cancels in Shepard and MLS functions:
      w(q) = 1 - 6 q^2 + 6 q^3  (0 <= q < 1/2),  2 (1 - q)^3  (1/2 <= q <= 1).
* Shepard functions W^S_I = W_I / sum_K W_K, eq (28) / (43), exact gradient.
* Trial functions Psi_J: MLS, linear basis p = (1, x, y), eqs (37)-(42)
  (basis shifted to the evaluation point and scaled by R; same Psi).
* Trial gradient: Krongauz-Belytschko correction, eqs (26)-(32):
      G_J(x) = a(x) . grad W^S_J(x),  A a^T = I  (31),
      A_ik = sum_J d_i W^S_J (X_J - x)_k  (= eq 31's sum_J d_i W^S_J X_J,k,
      since sum_J grad W^S_J = 0), so sum_J G_J (x) X_J = I  (29).
* Petrov-Galerkin, sec. 4.1.1, eqs (44)-(51), small strain: test Phi_I =
  W^S_I with exact gradients, trial Psi_J with assumed gradient G_J:
      K_IJ = sum_q w_q B_test_I(x_q)^T D B_trial_J(x_q)        (51)
      f_I  = int_{Gamma_t} Phi_I t dGamma                      (50)
  B from (grad W^S_I) and (G_J) resp.; plane-stress D, engineering shear.
* Stress-point integration, sec. 5.2, eqs (63)-(65), Table 1 "KBM (si)":
  quadrature points = particles + one stress point at the centre of every
  lattice square (001 Fig. 2); weights = areas of the cells of the joint
  Voronoi diagram clipped to the rectangle: h^2/2 interior particles and all
  stress points, h^2/4 edge particles, h^2/8 corner particles (eq 65: the
  weights sum to L*D, checked; also checked by brute-force nearest-point
  area counting at the two coarsest ny).
* Traction integral (50) on x = L (and the patch-test sides): rule (i)
  "nodal" = the side's particles with their Voronoi lengths (h; h/2 at the
  ends) [default], or (ii) "gauss" = 4 Gauss points per particle segment
  (--traction).
* Error norms: relative L2 of u, eqs (71)-(72), and relative energy norm,
  eqs (73)-(74) taken as sqrt(int (e^h - e)^T D (e^h - e)) /
  sqrt(int e^T D e), e^h from the method's own gradient (G for KBM, the MLS
  derivative for EFG), on an independent fine rule: a uniform grid with
  4 x 4 cells per lattice square, 4 x 4 Gauss points each.

Variants (--variant NAME, "all" = every one)
--------------------------------------------
  default     KBM si as 001 writes it (KB grad, Shepard test, stress points)
  vci1        + linear VCI (Chen, Hillman & Rueter 2013): grad Phi_I += c_I on
              supp(I), sum_q w_q grad~Phi_I = oint Phi_I n dGamma
  vci2        + quadratic VCI (not in 001): grad~Phi_I = grad W^S_I + xi_I +
              eta_I (x - x_I) on supp(I), 6 unknowns per I, so that
                 sum_q w_q grad~Phi_I           = oint Phi_I n              (2)
                 sum_q w_q [grad~Phi_I x^T + Phi_I Id] = oint Phi_I n x^T   (4)
              (the 6x6 system is block-diagonal: two copies, one per gradient
              component, of the 3x3 moment matrix sum_q w [1,d][1,d]^T,
              d = (x_q - x_I)/h; the second identity is imposed in the
              equivalent form with x - x_I in place of x)
  gauss       KB/Shepard with 4x4 Gauss points per lattice square, no VCI
  efg         Bubnov-Galerkin EFG (MLS test and trial, MLS derivatives),
              4x4 Gauss per lattice square (control)
  default-d2.0, default-d3.0, vci2-d2.0, vci2-d3.0   dmax = R/h = 2 and 3
  default-tgauss, vci1-tgauss, vci2-tgauss   traction rule (ii) instead of (i)
  vci1-cb, vci2-cb, vci2-cb-d2.0, vci2-cb-d3.0, vci2-cb-tgauss
              VCI with the boundary integrals taken by the discrete system's
              OWN boundary rules ("consistent"): the traction rule on the three
              loaded sides and, on x = 0, the multiplier points with their
              Voronoi lengths.  Reason: the point multipliers enter row I as
              sum_b Phi_I(x_b) lambda_b, so the exact reaction can only be
              represented if the divergence identity holds with that nodal rule
              on x = 0; with the 6-Gauss oint of vci1/vci2 the linear patch
              test fails at O(h) in the nodal values (O(1) in the strains next
              to x = 0), with the consistent rule it passes to ~1e-11.
  vci2-gauss, vci2-cb-gauss, vci2-cb-gauss-d2.0   quadratic VCI with 4x4 Gauss
              cells instead of stress points (extra)
Numerics: the multiplier rows/columns are scaled by mean(diag K) (E = 3e7:
unscaled, the saddle matrix has singular values down to 1e-15 of the largest
and the patch test loses 4-5 digits); sparse LU (SuperLU, COLAMD).
Diagnostics (default, at every ny): the linear patch test (exact linear u on
x = 0, its constant sigma n on the three other sides), the first-order
divergence residual r_I = sum_q w_q grad Phi_I - oint Phi_I n (interior /
boundary-near I), and the interior second-order residual
Q_I = sum_q w_q [grad Phi_I (x_q - x_I)^T + Phi_I Id] (4 entries; its
boundary term vanishes for interior I; it must be 0 for consistency).

Run:  /usr/bin/python3 tests/reference/kbm_cantilever_2d.py
          [--variant NAME|all] [--dmax D] [--ny 5,9,17,33] [--traction nodal|gauss]
      --variant takes "all", "diag" (diagnostics only) or a comma list.
      Default (--variant all, ny 5,9,17,33): about 2.5 min on one core.
      ny = 65 costs about 20-45 s per variant (e.g. --ny 5,9,17,33,65
      --variant default,vci1,vci2,vci2-cb,efg: ~3 min).
"""

import argparse
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree

# ---------------------------------------------------------------------------
# Problem data
# ---------------------------------------------------------------------------
LEN, DEP = 48.0, 12.0
EMOD, NU, PLOAD = 3.0e7, 0.3, 1000.0
IMOM = DEP ** 3 / 12.0
DMAT = EMOD / (1 - NU ** 2) * np.array([[1.0, NU, 0.0],
                                        [NU, 1.0, 0.0],
                                        [0.0, 0.0, (1 - NU) / 2]])


def u_exact(X):
    x, y = X[:, 0], X[:, 1]
    c = PLOAD / (6 * EMOD * IMOM)
    ux = -c * y * ((6 * LEN - 3 * x) * x + (2 + NU) * (y ** 2 - DEP ** 2 / 4))
    uy = c * (3 * NU * y ** 2 * (LEN - x) + (4 + 5 * NU) * DEP ** 2 * x / 4
              + (3 * LEN - x) * x ** 2)
    return np.stack([ux, uy], axis=1)


def eps_exact(X):
    """(e_xx, e_yy, gamma_xy) from the derivatives of u_exact."""
    x, y = X[:, 0], X[:, 1]
    c = PLOAD / (6 * EMOD * IMOM)
    exx = -c * y * (6 * LEN - 6 * x)
    duxdy = -c * ((6 * LEN - 3 * x) * x + (2 + NU) * (3 * y ** 2 - DEP ** 2 / 4))
    duydx = c * (-3 * NU * y ** 2 + (4 + 5 * NU) * DEP ** 2 / 4
                 + 6 * LEN * x - 3 * x ** 2)
    eyy = c * 6 * NU * y * (LEN - x)
    return np.stack([exx, eyy, duxdy + duydx], axis=1)


def sig_exact(X):
    x, y = X[:, 0], X[:, 1]
    sxx = -PLOAD * (LEN - x) * y / IMOM
    sxy = PLOAD / (2 * IMOM) * (DEP ** 2 / 4 - y ** 2)
    return np.stack([sxx, 0 * x, sxy], axis=1)


def traction(sig, nrm):
    """t = sigma n, sig = (s_xx, s_yy, s_xy) rows."""
    return np.stack([sig[:, 0] * nrm[:, 0] + sig[:, 2] * nrm[:, 1],
                     sig[:, 2] * nrm[:, 0] + sig[:, 1] * nrm[:, 1]], axis=1)


# linear patch field u = A0 + A1 x: constants chosen arbitrarily
PATCH_C = np.array([0.3e-3, -0.2e-3])
PATCH_G = np.array([[1.1e-4, 0.7e-4], [-0.4e-4, 0.9e-4]])   # du_i/dx_j


def u_patch(X):
    return PATCH_C[None, :] + X @ PATCH_G.T


def eps_patch(X):
    e = np.array([PATCH_G[0, 0], PATCH_G[1, 1], PATCH_G[0, 1] + PATCH_G[1, 0]])
    return np.tile(e, (X.shape[0], 1))


def sig_patch(X):
    return eps_patch(X) @ DMAT.T


# ---------------------------------------------------------------------------
# Kernel (001 eq 14 normalised to support radius 1) and shape functions
# ---------------------------------------------------------------------------
def spline(q):
    w = np.zeros_like(q)
    dw = np.zeros_like(q)
    a = q < 0.5
    b = (q >= 0.5) & (q < 1.0)
    w[a] = 1 - 6 * q[a] ** 2 + 6 * q[a] ** 3
    dw[a] = -12 * q[a] + 18 * q[a] ** 2
    w[b] = 2 * (1 - q[b]) ** 3
    dw[b] = -6 * (1 - q[b]) ** 2
    return w, dw


class Cloud:
    """Particles, their kd-tree and the support radius."""

    def __init__(self, ny, dmax):
        self.ny = ny
        self.nx = 4 * (ny - 1) + 1
        self.h = DEP / (ny - 1)
        self.R = dmax * self.h
        xs = np.linspace(0.0, LEN, self.nx)
        ys = np.linspace(-DEP / 2, DEP / 2, ny)
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        self.xp = np.stack([gx.ravel(), gy.ravel()], axis=1)
        self.N = self.xp.shape[0]
        self.tree = cKDTree(self.xp)
        # neighbour-list width: the most particles within R of any point
        # (attained in the interior; sampled over one lattice square)
        s = (np.arange(41) / 40.0) * self.h
        g = np.stack(np.meshgrid(s, s, indexing="ij"), -1).reshape(-1, 2)
        g += np.array([LEN / 2 - (LEN / 2) % self.h, 0.0])
        self.kmax = int(self.tree.query_ball_point(g, self.R, return_length=True).max())
        tol = 1e-9 * self.h
        self.on_x0 = np.abs(self.xp[:, 0]) < tol
        # distance of each particle to the boundary
        self.dist_b = np.minimum.reduce([self.xp[:, 0], LEN - self.xp[:, 0],
                                         self.xp[:, 1] + DEP / 2,
                                         DEP / 2 - self.xp[:, 1]])

    def shapes(self, X, mls=True):
        """Shape data at points X (n, 2), neighbour-list form (n, k):
        idx (N marks an empty slot), W, S, dS (n,k,2), G (n,k,2) [KB],
        Psi, dPsi (n,k,2) [MLS]."""
        X = np.asarray(X, float)
        R = self.R
        kmax = self.kmax
        dist, idx = self.tree.query(X, k=kmax, distance_upper_bound=R)
        if np.isfinite(dist[:, -1]).any():     # lists may be full: widen
            kmax = int(self.tree.query_ball_point(X, R, return_length=True).max())
            self.kmax = max(self.kmax, kmax)
            dist, idx = self.tree.query(X, k=self.kmax + 1, distance_upper_bound=R)
        valid = idx < self.N
        idx0 = np.where(valid, idx, 0)
        diff = X[:, None, :] - self.xp[idx0]              # x - x_J
        dist = np.where(valid, np.sqrt((diff ** 2).sum(-1)), R)
        q = np.minimum(dist / R, 1.0)
        W, dwq = spline(q)
        W = np.where(valid, W, 0.0)
        with np.errstate(invalid="ignore", divide="ignore"):
            fac = np.where(dist > 0, dwq / (R * dist), 0.0)
        dW = (fac * valid)[..., None] * diff               # (n,k,2)
        # Shepard, eq (28)
        sW = W.sum(1)
        sdW = dW.sum(1)
        S = W / sW[:, None]
        dS = (dW - S[..., None] * sdW[:, None, :]) / sW[:, None, None]
        # KB correction, eqs (29)-(32)
        A = np.matmul(dS.transpose(0, 2, 1), -diff)       # A_ik, eq (31)
        G = np.matmul(dS, np.linalg.inv(A).transpose(0, 2, 1))
        out = dict(idx=idx0, valid=valid & (W > 0), W=W, S=S, dS=dS, G=G)
        if mls:
            # MLS eqs (38)-(42), p_J = (1, (x_J - x)/R, (y_J - y)/R)
            s = -diff / R
            p = np.concatenate([np.ones_like(W)[..., None], s], axis=2)
            pt = p.transpose(0, 2, 1)
            Am = np.matmul(pt * W[:, None, :], p)
            Ai = np.linalg.inv(Am)
            gam = Ai[:, :, 0]                              # A^{-1} (1,0,0)
            pg = np.matmul(p, gam[..., None])[..., 0]
            Psi = W * pg
            dPsi = np.empty_like(dW)
            for a in range(2):
                dA = np.matmul(pt * dW[:, None, :, a], p)
                rhs = -np.matmul(dA, gam[..., None])
                rhs[:, 1 + a, 0] += 1.0 / R
                dgam = np.matmul(Ai, rhs)
                dPsi[..., a] = dW[..., a] * pg + W * np.matmul(p, dgam)[..., 0]
            out["Psi"] = Psi
            out["dPsi"] = dPsi
        return out


# ---------------------------------------------------------------------------
# Quadrature rules
# ---------------------------------------------------------------------------
def rule_stress(cl):
    """Particles + quad-centre stress points, joint-Voronoi weights (63)-(65)."""
    h = cl.h
    xp = cl.xp
    tol = 1e-9 * h
    onx = (np.abs(xp[:, 0]) < tol) | (np.abs(xp[:, 0] - LEN) < tol)
    ony = (np.abs(xp[:, 1] + DEP / 2) < tol) | (np.abs(xp[:, 1] - DEP / 2) < tol)
    wp = np.full(cl.N, h * h / 2)
    wp[onx ^ ony] = h * h / 4
    wp[onx & ony] = h * h / 8
    xs = (np.arange(cl.nx - 1) + 0.5) * h
    ys = -DEP / 2 + (np.arange(cl.ny - 1) + 0.5) * h
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    xsp = np.stack([gx.ravel(), gy.ravel()], axis=1)
    wsp = np.full(xsp.shape[0], h * h / 2)
    return np.vstack([xp, xsp]), np.concatenate([wp, wsp])


def gauss_1d(n):
    return np.polynomial.legendre.leggauss(n)


def rule_cells(cl, ng, nsub=1):
    """ng x ng Gauss points on each of (nsub x nsub) sub-cells of every
    lattice square (eqs 66-69)."""
    xi, wi = gauss_1d(ng)
    hx = cl.h / nsub
    ex = np.arange((cl.nx - 1) * nsub) * hx
    ey = -DEP / 2 + np.arange((cl.ny - 1) * nsub) * hx
    px = (ex[:, None] + 0.5 * hx * (1 + xi[None, :])).ravel()
    py = (ey[:, None] + 0.5 * hx * (1 + xi[None, :])).ravel()
    wx = np.tile(0.5 * hx * wi, ex.size)
    wy = np.tile(0.5 * hx * wi, ey.size)
    gx, gy = np.meshgrid(px, py, indexing="ij")
    X = np.stack([gx.ravel(), gy.ravel()], axis=1)
    w = np.outer(wx, wy).ravel()
    return X, w


def side_rule(cl, side, kind, ng=4):
    """1D rule on one side: (points, weights, outward normal).  kind 'nodal'
    = the side's particles with Voronoi lengths; 'gauss' = ng Gauss points
    per particle segment."""
    h = cl.h
    if side in ("left", "right"):
        n = cl.ny
        t = -DEP / 2 + np.arange(n) * h
        x0 = 0.0 if side == "left" else LEN
        mk = lambda s: np.stack([np.full_like(s, x0), s], axis=1)
        nrm = (-1.0, 0.0) if side == "left" else (1.0, 0.0)
    else:
        n = cl.nx
        t = np.arange(n) * h
        y0 = -DEP / 2 if side == "bottom" else DEP / 2
        mk = lambda s: np.stack([s, np.full_like(s, y0)], axis=1)
        nrm = (0.0, -1.0) if side == "bottom" else (0.0, 1.0)
    if kind == "nodal":
        s = t
        w = np.full(n, h)
        w[0] = w[-1] = h / 2
    else:
        xi, wi = gauss_1d(ng)
        s = (t[:-1, None] + 0.5 * h * (1 + xi[None, :])).ravel()
        w = np.tile(0.5 * h * wi, n - 1)
    X = mk(s)
    return X, w, np.tile(np.array(nrm), (X.shape[0], 1))


def boundary_rule(cl, kind, ng):
    parts = [side_rule(cl, s, kind, ng) for s in ("left", "right", "bottom", "top")]
    return tuple(np.concatenate([p[i] for p in parts]) for i in range(3))


# ---------------------------------------------------------------------------
# Sparse helpers
# ---------------------------------------------------------------------------
def bmat_strain(sh, grad, ncols):
    """Sparse strain-displacement matrix (3 nq x 2N) from a gradient array
    grad (nq, k, 2) on the neighbour lists of sh."""
    nq, k = sh["idx"].shape
    v = sh["valid"]
    q = np.broadcast_to(np.arange(nq)[:, None], (nq, k))[v]
    J = sh["idx"][v]
    gx, gy = grad[..., 0][v], grad[..., 1][v]
    rows = np.concatenate([3 * q, 3 * q + 1, 3 * q + 2, 3 * q + 2])
    cols = np.concatenate([2 * J, 2 * J + 1, 2 * J, 2 * J + 1])
    vals = np.concatenate([gx, gy, gy, gx])
    return sp.csr_matrix((vals, (rows, cols)), shape=(3 * nq, ncols))


def value_matrix(sh, val, ncols_nodes):
    """Sparse (n x N) matrix of function values val (n, k)."""
    n, k = sh["idx"].shape
    v = sh["valid"]
    r = np.broadcast_to(np.arange(n)[:, None], (n, k))[v]
    return sp.csr_matrix((val[v], (r, sh["idx"][v])), shape=(n, ncols_nodes))


def vec_dofs(Vm):
    """(n x N) value matrix -> (2n x 2N) for the two displacement components."""
    return sp.kron(Vm, sp.identity(2), format="csr")


# ---------------------------------------------------------------------------
# Variants
# ---------------------------------------------------------------------------
VARIANTS = {
    # name: dict(test, grad, quad, vci, dmax override, traction override)
    "default": dict(test="shepard", grad="kb", quad="si", vci=0,
                    desc="KBM si (001): KB grad, Shepard test, particles + quad-centre stress points"),
    "vci1": dict(test="shepard", grad="kb", quad="si", vci=1,
                 desc="default + linear VCI on the test gradients"),
    "vci2": dict(test="shepard", grad="kb", quad="si", vci=2,
                 desc="default + quadratic VCI on the test gradients"),
    "gauss": dict(test="shepard", grad="kb", quad="gauss4", vci=0,
                  desc="KB/Shepard, 4x4 Gauss per lattice square, no VCI"),
    "efg": dict(test="mls", grad="mls", quad="gauss4", vci=0,
                desc="EFG Bubnov-Galerkin (MLS/MLS, MLS derivatives), 4x4 Gauss per lattice square"),
    "default-d2.0": dict(test="shepard", grad="kb", quad="si", vci=0, dmax=2.0,
                         desc="default, dmax = 2.0"),
    "default-d3.0": dict(test="shepard", grad="kb", quad="si", vci=0, dmax=3.0,
                         desc="default, dmax = 3.0"),
    "vci2-d2.0": dict(test="shepard", grad="kb", quad="si", vci=2, dmax=2.0,
                      desc="quadratic VCI, dmax = 2.0"),
    "vci2-d3.0": dict(test="shepard", grad="kb", quad="si", vci=2, dmax=3.0,
                      desc="quadratic VCI, dmax = 3.0"),
    "default-tgauss": dict(test="shepard", grad="kb", quad="si", vci=0, traction="gauss",
                           desc="default, traction rule (ii) 4 Gauss/segment"),
    "vci1-tgauss": dict(test="shepard", grad="kb", quad="si", vci=1, traction="gauss",
                        desc="linear VCI, traction rule (ii) 4 Gauss/segment"),
    "vci2-tgauss": dict(test="shepard", grad="kb", quad="si", vci=2, traction="gauss",
                        desc="quadratic VCI, traction rule (ii) 4 Gauss/segment"),
    "vci1-cb": dict(test="shepard", grad="kb", quad="si", vci=1, vci_bnd="consistent",
                    desc="linear VCI, boundary integral by the system's own boundary rule"),
    "vci2-cb": dict(test="shepard", grad="kb", quad="si", vci=2, vci_bnd="consistent",
                    desc="quadratic VCI, boundary integral by the system's own boundary rule"),
    "vci2-cb-d2.0": dict(test="shepard", grad="kb", quad="si", vci=2, vci_bnd="consistent",
                         dmax=2.0, desc="quadratic VCI (consistent boundary rule), dmax = 2.0"),
    "vci2-cb-d3.0": dict(test="shepard", grad="kb", quad="si", vci=2, vci_bnd="consistent",
                         dmax=3.0, desc="quadratic VCI (consistent boundary rule), dmax = 3.0"),
    "vci2-cb-tgauss": dict(test="shepard", grad="kb", quad="si", vci=2, vci_bnd="consistent",
                           traction="gauss",
                           desc="quadratic VCI (consistent boundary rule), traction rule (ii)"),
    "vci2-cb-gauss": dict(test="shepard", grad="kb", quad="gauss4", vci=2, vci_bnd="consistent",
                          desc="quadratic VCI (consistent boundary rule), 4x4 Gauss per lattice square"),
    "vci2-cb-gauss-d2.0": dict(test="shepard", grad="kb", quad="gauss4", vci=2,
                               vci_bnd="consistent", dmax=2.0,
                               desc="quadratic VCI (consistent boundary rule), 4x4 Gauss, dmax = 2.0"),
    "vci2-gauss": dict(test="shepard", grad="kb", quad="gauss4", vci=2,
                       desc="quadratic VCI with 4x4 Gauss per lattice square"),
}



class Discretisation:
    def __init__(self, ny, dmax, name, traction_kind):
        v = VARIANTS[name]
        self.name = name
        self.dmax = v.get("dmax", dmax)
        self.tkind = v.get("traction", traction_kind)
        self.cl = cl = Cloud(ny, self.dmax)
        N = cl.N
        if v["quad"] == "si":
            self.xq, self.wq = rule_stress(cl)
        else:
            self.xq, self.wq = rule_cells(cl, 4)
        shq = cl.shapes(self.xq, mls=True)
        self.shq = shq
        if v["test"] == "shepard":
            T, dT = shq["S"], shq["dS"].copy()
        else:
            T, dT = shq["Psi"], shq["dPsi"].copy()
        Gt = shq["G"] if v["grad"] == "kb" else shq["dPsi"]
        self.test, self.grad = v["test"], v["grad"]

        # boundary integrals oint Phi_I n and oint Phi_I n (x - x_I)^T, by the
        # VCI boundary rule: "gauss6" = 6 Gauss points per particle segment on
        # all four sides (accurate); "consistent" = the rule the discrete
        # system itself uses on each side: the traction rule on the three
        # loaded sides and the particle points with Voronoi lengths on x = 0
        # (the point multipliers act as forces sum_b Phi_I(x_b) lambda_b)
        self.vci_bnd = v.get("vci_bnd", "gauss6")
        self.bI, self.B2I = self.boundary_moments(v["test"], self.vci_bnd)

        # raw residuals (before VCI)
        self.r1_raw, self.Q_raw = self.residuals(T, dT)
        if v["vci"] == 1:
            idx, val = shq["idx"], shq["valid"]
            wI = np.bincount(idx[val], weights=np.broadcast_to(
                self.wq[:, None], val.shape)[val], minlength=N)
            c = -self.r1_raw / wI[:, None]                  # (N, 2)
            dT = dT + val[..., None] * c[idx]
        elif v["vci"] == 2:
            dT = self.vci2(T, dT)
        self.r1, self.Q = self.residuals(T, dT)
        self.T, self.dT, self.Gt = T, dT, Gt

        # stiffness (51)
        Bt = bmat_strain(shq, dT, 2 * N)
        Br = bmat_strain(shq, Gt, 2 * N)
        Dq = sp.kron(sp.diags(self.wq), sp.csr_matrix(DMAT), format="csr")
        self.K = (Bt.T @ (Dq @ Br)).tocsr()
        self.Br = Br

        # Lagrange multipliers on x = 0: constraints with Psi, multiplier with Phi
        xb = cl.xp[cl.on_x0]
        self.xb = xb
        shb = cl.shapes(xb, mls=True)
        Cpsi = vec_dofs(value_matrix(shb, shb["Psi"], N))
        Tb = shb["S"] if v["test"] == "shepard" else shb["Psi"]
        Cphi = vec_dofs(value_matrix(shb, Tb, N))
        # scale the multiplier rows/columns like K (E ~ 3e7: unscaled, the
        # saddle matrix has singular values down to ~1e-15 of the largest)
        self.cscale = np.abs(self.K.diagonal()).mean()
        M = sp.bmat([[self.K, self.cscale * Cphi.T], [self.cscale * Cpsi, None]],
                    format="csc")
        self.lu = spla.splu(M, permc_spec="COLAMD")

        # traction rule on the three non-Dirichlet sides
        parts = [side_rule(cl, s, self.tkind, 4) for s in ("right", "bottom", "top")]
        self.xt, self.wt, self.nt = (np.concatenate([p[i] for p in parts]) for i in range(3))
        sht = cl.shapes(self.xt, mls=(v["test"] == "mls"))
        Tt = sht["S"] if v["test"] == "shepard" else sht["Psi"]
        self.Tt = vec_dofs(value_matrix(sht, Tt, N))

    # -- consistency ------------------------------------------------------
    def boundary_moments(self, test, rule):
        cl = self.cl
        if rule == "consistent":
            parts = [side_rule(cl, "left", "nodal")] + [
                side_rule(cl, s, self.tkind, 4) for s in ("right", "bottom", "top")]
            Xb, wb, nb = (np.concatenate([p[i] for p in parts]) for i in range(3))
        else:
            Xb, wb, nb = boundary_rule(cl, "gauss", int(rule[5:]))
        sh = cl.shapes(Xb, mls=(test == "mls"))
        T = sh["S"] if test == "shepard" else sh["Psi"]
        idx, val = sh["idx"], sh["valid"]
        N = cl.N
        bI = np.zeros((N, 2))
        B2 = np.zeros((N, 2, 2))
        wT = (wb[:, None] * T)[val]
        I = idx[val]
        nbq = np.broadcast_to(nb[:, None, :], idx.shape + (2,))[val]
        Xq = np.broadcast_to(Xb[:, None, :], idx.shape + (2,))[val]
        d = Xq - cl.xp[I]
        for a in range(2):
            bI[:, a] = np.bincount(I, weights=wT * nbq[:, a], minlength=N)
            for k in range(2):
                B2[:, a, k] = np.bincount(I, weights=wT * nbq[:, a] * d[:, k], minlength=N)
        return bI, B2

    def residuals(self, T, dT):
        """r1_I = sum_q w grad Phi_I - oint Phi_I n;
        Q_I = sum_q w [grad Phi_I (x_q - x_I)^T + Phi_I Id] - oint Phi_I n (x - x_I)^T."""
        sh, N = self.shq, self.cl.N
        idx, val = sh["idx"], sh["valid"]
        I = idx[val]
        w = np.broadcast_to(self.wq[:, None], val.shape)[val]
        g = dT[val]
        Phi = T[val]
        d = np.broadcast_to(self.xq[:, None, :], idx.shape + (2,))[val] - self.cl.xp[I]
        r1 = np.zeros((N, 2))
        Q = np.zeros((N, 2, 2))
        for a in range(2):
            r1[:, a] = np.bincount(I, weights=w * g[:, a], minlength=N)
            for k in range(2):
                Q[:, a, k] = np.bincount(I, weights=w * (g[:, a] * d[:, k]
                                                          + Phi * (a == k)), minlength=N)
        return r1 - self.bI, Q - self.B2I

    def vci2(self, T, dT):
        sh, N, h = self.shq, self.cl.N, self.cl.h
        idx, val = sh["idx"], sh["valid"]
        I = idx[val]
        w = np.broadcast_to(self.wq[:, None], val.shape)[val]
        dh = (np.broadcast_to(self.xq[:, None, :], idx.shape + (2,))[val]
              - self.cl.xp[I]) / h
        P = np.concatenate([np.ones((dh.shape[0], 1)), dh], axis=1)   # [1, d/h]
        M = np.zeros((N, 3, 3))
        for i in range(3):
            for j in range(3):
                M[:, i, j] = np.bincount(I, weights=w * P[:, i] * P[:, j], minlength=N)
        r1, Q = self.residuals(T, dT)
        # rhs for component a: -[r1_a, Q_a1/h, Q_a2/h]
        rhs = -np.stack([r1, Q[:, :, 0] / h, Q[:, :, 1] / h], axis=1)  # (N,3,2)
        coef = np.linalg.solve(M, rhs)                                  # (N,3,2)
        corr = np.einsum("mi,mia->ma", P, coef[I])
        dT = dT.copy()
        dT[val] += corr
        return dT

    # -- solve --------------------------------------------------------------
    def solve(self, ufun, sigfun):
        N = self.cl.N
        t = traction(sigfun(self.xt), self.nt)
        f = self.Tt.T @ (self.wt[:, None] * t).ravel()
        g = self.cscale * ufun(self.xb).ravel()
        sol = self.lu.solve(np.concatenate([f, g]))
        return sol[:2 * N].reshape(N, 2)

    def patch_test(self):
        """Exact linear field: max nodal error of u^h(x_J) and max strain
        error at the quadrature points, both relative."""
        cl = self.cl
        uJ = self.solve(u_patch, sig_patch)
        shp = cl.shapes(cl.xp, mls=True)
        uh = np.einsum("nj,nja->na", shp["Psi"], uJ[shp["idx"]])
        ue = u_patch(cl.xp)
        enod = np.max(np.abs(uh - ue)) / np.max(np.abs(ue))
        eh = (self.Br @ uJ.ravel()).reshape(-1, 3)
        ee = eps_patch(self.xq)
        estr = np.max(np.abs(eh - ee)) / np.max(np.abs(ee))
        return enod, estr

    def exact_stress_residual(self, rule="gauss12"):
        """Row consistency with the exact cantilever stress (div sigma = 0):
        rho_I = sum_q w_q gradPhi_I . sigma(x_q) - oint Phi_I sigma n dGamma,
        oint by 12 Gauss points per particle segment on all four sides
        (rule "gauss12": the exact boundary integral) or by the system's own
        boundary rule (rule "own": traction rule on the loaded sides, the
        multiplier points with Voronoi lengths on x = 0, i.e. the multipliers
        lambda_b = l_b sigma n(x_b)); the test-side integration error that the
        discrete equations carry for the exact stress.  Divided by h max|sigma|."""
        cl, sh = self.cl, self.shq
        idx, val = sh["idx"], sh["valid"]
        sig = sig_exact(self.xq)
        g = self.dT
        fx = g[..., 0] * sig[:, None, 0] + g[..., 1] * sig[:, None, 2]
        fy = g[..., 0] * sig[:, None, 2] + g[..., 1] * sig[:, None, 1]
        w = self.wq[:, None]
        rho = np.stack([np.bincount(idx[val], weights=(w * fx)[val], minlength=cl.N),
                        np.bincount(idx[val], weights=(w * fy)[val], minlength=cl.N)], 1)
        if rule == "own":
            parts = [side_rule(cl, "left", "nodal")] + [
                side_rule(cl, s, self.tkind, 4) for s in ("right", "bottom", "top")]
            Xb, wb, nb = (np.concatenate([p[i] for p in parts]) for i in range(3))
        else:
            Xb, wb, nb = boundary_rule(cl, "gauss", 12)
        shb = cl.shapes(Xb, mls=(self.test == "mls"))
        Tb = shb["S"] if self.test == "shepard" else shb["Psi"]
        t = traction(sig_exact(Xb), nb)
        vb = shb["valid"]
        for a in range(2):
            rho[:, a] -= np.bincount(shb["idx"][vb], weights=(wb[:, None] * Tb * t[:, None, a])[vb],
                                     minlength=cl.N)
        smax = np.abs(sig_exact(cl.xp)).max()
        return rho / (cl.h * smax)

    def split(self, arr):
        """max |.| over interior (dist to boundary >= 2R) and boundary-near I."""
        a = np.abs(arr).reshape(arr.shape[0], -1).max(1)
        inner = self.cl.dist_b >= 2 * self.cl.R - 1e-9
        ai = a[inner].max() if inner.any() else np.nan
        return ai, a[~inner].max(), inner


# ---------------------------------------------------------------------------
# Error norms (71)-(74) on the independent fine rule
# ---------------------------------------------------------------------------
def errors(cl, sols, nsub=4, ng=4, chunk=50000):
    """Relative L2 and energy errors of several solutions on one cloud.
    sols: list of (uJ (N,2), grad kind 'kb' | 'mls').  Fine rule: nsub x nsub
    cells per lattice square, ng x ng Gauss points each (independent of every
    rule used by the methods)."""
    Xf, wf = rule_cells(cl, ng, nsub)
    acc = np.zeros((len(sols), 2))
    den = np.zeros(2)
    for i in range(0, Xf.shape[0], chunk):
        X, w = Xf[i:i + chunk], wf[i:i + chunk]
        sh = cl.shapes(X, mls=True)
        idx = sh["idx"]
        ue, ee = u_exact(X), eps_exact(X)
        den += [np.sum(w * (ue ** 2).sum(1)), np.sum(w * ((ee @ DMAT) * ee).sum(1))]
        for s, (uJ, gk) in enumerate(sols):
            uI = uJ[idx]                                    # (n,k,2)
            uh = (sh["Psi"][..., None] * uI).sum(1)
            G = sh["G"] if gk == "kb" else sh["dPsi"]
            Fh = np.matmul(uI.transpose(0, 2, 1), G)        # du_a/dx_b
            eh = np.stack([Fh[:, 0, 0], Fh[:, 1, 1], Fh[:, 0, 1] + Fh[:, 1, 0]], 1)
            de = eh - ee
            acc[s, 0] += np.sum(w * ((uh - ue) ** 2).sum(1))
            acc[s, 1] += np.sum(w * ((de @ DMAT) * de).sum(1))
    return np.sqrt(acc / den[None, :])


# ---------------------------------------------------------------------------
# Driver
# ---------------------------------------------------------------------------
def rates(hs, es):
    hs, es = np.asarray(hs), np.asarray(es)
    pair = np.log(es[:-1] / es[1:]) / np.log(hs[:-1] / hs[1:])
    ls = np.polyfit(np.log(hs), np.log(es), 1)[0] if len(hs) > 1 else np.nan
    return pair, ls


def effective(name, dmax, tkind):
    v = VARIANTS[name]
    return v.get("dmax", dmax), v.get("traction", tkind)


def run_variants(names, dmax, nys, tkind):
    """Solve every variant at every ny; one fine-rule error pass per
    (ny, dmax) for all variants sharing that particle cloud."""
    res = {n: [] for n in names}
    groups = {}
    for n in names:
        groups.setdefault(effective(n, dmax, tkind)[0], []).append(n)
    for ny in nys:
        for dm, members in groups.items():
            sols, info = [], []
            for n in members:
                t0 = time.time()
                d = Discretisation(ny, dmax, n, tkind)
                uJ = d.solve(u_exact, sig_exact)
                pn, ps = d.patch_test()
                sols.append((uJ, d.grad))
                info.append((n, d.cl.N, d.cl.h, pn, ps, np.max(np.abs(d.r1)),
                             time.time() - t0))
                cl = d.cl
                del d
            t0 = time.time()
            errs = errors(cl, sols)
            te = (time.time() - t0) / len(members)
            for (n, N, h, pn, ps, r1, t), (eL2, eEn) in zip(info, errs):
                res[n].append((ny, N, h, eL2, eEn, pn, ps, r1, t + te))
        print(f"  [ny = {ny} done]", file=sys.stderr)
    for n in names:
        print_table(n, dmax, tkind, res[n])
    return res


def print_table(name, dmax, tkind, rows):
    v = VARIANTS[name]
    d0, tk = effective(name, dmax, tkind)
    print("=" * 100)
    print(f"variant {name}: {v['desc']}")
    vb = v.get("vci_bnd", "gauss6") if v["vci"] else "-"
    print(f"   dmax = {d0}, traction rule = "
          f"{'(i) particles with Voronoi lengths' if tk == 'nodal' else '(ii) 4 Gauss/segment'}"
          f", VCI boundary rule = {vb}")
    print("=" * 100)
    hs = [r[2] for r in rows]
    pL, lL = rates(hs, [r[3] for r in rows])
    pE, lE = rates(hs, [r[4] for r in rows])
    print(f"{'ny':>4} {'particles':>9} {'L2':>11} {'rate':>6} {'energy':>11} {'rate':>6} | "
          f"{'patch nod':>9} {'patch eps':>9} {'max|r1_I|':>9} {'time':>6}")
    for i, r in enumerate(rows):
        rl = "" if i == 0 else f"{pL[i - 1]:6.2f}"
        re = "" if i == 0 else f"{pE[i - 1]:6.2f}"
        print(f"{r[0]:4d} {r[1]:9d} {r[3]:11.4e} {rl:>6} {r[4]:11.4e} {re:>6} | "
              f"{r[5]:9.1e} {r[6]:9.1e} {r[7]:9.1e} {r[8]:5.1f}s")
    print(f"least-squares rates: L2 {lL:.2f}, energy {lE:.2f}"
          + (f"   (last three ny: L2 {rates(hs[-3:], [r[3] for r in rows][-3:])[1]:.2f},"
             f" energy {rates(hs[-3:], [r[4] for r in rows][-3:])[1]:.2f})" if len(rows) > 3 else ""))
    print()
    sys.stdout.flush()


def voronoi_check(cl, xq, wq, m=160):
    """Brute-force area of each quadrature point's cell: nearest-point
    assignment of an m x m sub-grid of every lattice square (shifted off the
    symmetry lines).  Returns max |area - w| / (h^2/2)."""
    h = cl.h
    s = (np.arange(m) + 0.5 + 0.1234567) / m
    s = s[s < 1.0]
    pts_x = ((np.arange(cl.nx - 1)[:, None] + s[None, :]) * h).ravel()
    pts_y = (-DEP / 2 + (np.arange(cl.ny - 1)[:, None] + s[None, :]) * h).ravel()
    gx, gy = np.meshgrid(pts_x, pts_y, indexing="ij")
    P = np.stack([gx.ravel(), gy.ravel()], axis=1)
    _, nearest = cKDTree(xq).query(P)
    area = np.bincount(nearest, minlength=xq.shape[0]) * (LEN * DEP / P.shape[0])
    return np.max(np.abs(area - wq)) / (h * h / 2)


def diagnostics(dmax, nys, tkind, name="default"):
    print("=" * 100)
    print(f"diagnostics, variant {name} (dmax = {VARIANTS[name].get('dmax', dmax)})")
    print("  sum w   : |sum_q w_q - L D| / (L D) for the stress-point rule (eq 65)")
    print("  voronoi : brute-force Voronoi areas vs the weights, max |diff|/(h^2/2) (ny <= 9)")
    print("  patch   : linear patch test, rel. max nodal error of u^h(x_J), rel. max strain error at x_q")
    print("  r1 int/bnd : max_I |sum_q w grad Phi_I - oint Phi_I n|, interior (dist >= 2R) / boundary-near,")
    print("               also divided by h (the size of oint/sum of |grad Phi_I| ~ h)")
    print("  Q int   : interior second-order residual sum_q w [grad Phi_I (x_q-x_I)^T + Phi_I Id],")
    print("            max over interior I of each entry, divided by sum_q w Phi_I (1D analogue: E_eff/E - 1)")
    print("  bnd rule: max_I |oint Phi_I n| change from 6 to 12 Gauss points per segment")
    print("=" * 100)
    print(f"{'ny':>4} {'sum w':>9} {'voronoi':>8} {'patch nod':>9} {'patch eps':>9} "
          f"{'r1 int':>9} {'r1 bnd':>9} {'r1bnd/h':>9} | {'Qxx/m':>9} {'Qxy/m':>9} "
          f"{'Qyx/m':>9} {'Qyy/m':>9} {'bnd rule':>8}")
    for ny in nys:
        d = Discretisation(ny, dmax, name, tkind)
        cl = d.cl
        sw = abs(d.wq.sum() - LEN * DEP) / (LEN * DEP)
        vor = voronoi_check(cl, d.xq, d.wq) if (ny <= 9 and VARIANTS[name]["quad"] == "si") else np.nan
        pn, ps = d.patch_test()
        ri, rb, inner = d.split(d.r1)
        # interior second-order residual relative to sum_q w Phi_I
        sh = d.shq
        mI = np.bincount(sh["idx"][sh["valid"]], weights=(d.wq[:, None] * d.T)[sh["valid"]],
                         minlength=cl.N)
        if inner.any():
            Qr = d.Q[inner] / mI[inner, None, None]
            qa = [Qr[:, a, k][np.argmax(np.abs(Qr[:, a, k]))] for a in range(2) for k in range(2)]
        else:
            qa = [np.nan] * 4
        b12, _ = d.boundary_moments(d.test, "gauss12")
        brule = np.max(np.abs(b12 - d.bI))
        print(f"{ny:4d} {sw:9.1e} {vor:8.1e} {pn:9.1e} {ps:9.1e} {ri:9.1e} {rb:9.1e} "
              f"{rb / cl.h:9.1e} | {qa[0]:+9.2e} {qa[1]:+9.2e} {qa[2]:+9.2e} {qa[3]:+9.2e} "
              f"{brule:8.1e}")
    # where the first-order residual sits, at the finest ny
    d = Discretisation(nys[-1], dmax, name, tkind)
    cl = d.cl
    a = np.abs(d.r1_raw).max(1) / cl.h
    print(f"raw r1_I/h (before VCI) at ny = {nys[-1]} by distance of x_I to the boundary (in h):")
    db = np.round(cl.dist_b / cl.h).astype(int)
    for k in range(0, int(np.ceil(2 * d.dmax)) + 2):
        sel = db == k
        if sel.any():
            print(f"   dist {k:2d} h: max {a[sel].max():.3e}  (n = {sel.sum()})")
    inner = cl.dist_b >= 2 * cl.R - 1e-9
    if inner.any():
        Qr = d.Q_raw[inner]
        print("raw interior Q_I / h^2 (one interior particle): ",
              np.array2string(Qr[0] / cl.h ** 2, precision=4))
    print()
    print("row consistency with the exact cantilever stress (div sigma = 0), traction rule", tkind)
    print("  rho_I = sum_q w grad~Phi_I . sigma(x_q) - oint Phi_I sigma n,  max_I |rho_I| / (h max|sigma|)")
    print("  int = interior I (dist >= 2R), all variants (exact oint);  for boundary-near I:")
    print("  ex = oint exact (12 Gauss/segment), own = oint by the system's own boundary rules")
    print("  (traction rule on the loaded sides, multiplier points with lambda_b = l_b sigma n on x = 0).")
    print("  The interior Q_I is isotropic (q Id): it multiplies div sigma = 0, so it cannot act here")
    cols = ["default", "vci1", "vci2", "vci1-cb", "vci2-cb"]
    print(f"{'ny':>4} {'max int':>9} " + " ".join(f"{c + ' ex':>11} {c + ' own':>12}" for c in cols))
    for ny in nys:
        line, rint = "", 0.0
        for c in cols:
            d = Discretisation(ny, dmax, c, tkind)
            ri, rb, _ = d.split(d.exact_stress_residual("gauss12"))
            _, ro, _ = d.split(d.exact_stress_residual("own"))
            rint = max(rint, ri) if np.isfinite(ri) else ri
            line += f"{rb:11.2e} {ro:12.2e} "
            del d
        print(f"{ny:4d} {rint:9.1e} " + line)
    print()
    sys.stdout.flush()


ALL = ["default", "vci1", "vci2", "gauss", "efg", "default-d2.0", "default-d3.0",
       "vci2-d2.0", "vci2-d3.0", "default-tgauss", "vci1-tgauss", "vci2-tgauss",
       "vci1-cb", "vci2-cb", "vci2-cb-d2.0", "vci2-cb-d3.0", "vci2-cb-tgauss",
       "vci2-gauss", "vci2-cb-gauss", "vci2-cb-gauss-d2.0"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--variant", default="all",
                    help="all | diag (diagnostics only) | a comma-separated list of: "
                    + ", ".join(VARIANTS))
    ap.add_argument("--dmax", type=float, default=2.4)
    ap.add_argument("--ny", default="5,9,17,33")
    ap.add_argument("--traction", default="nodal", choices=["nodal", "gauss"])
    ap.add_argument("--no-diag", action="store_true")
    ap.add_argument("--json", metavar="FILE",
                    help="also write the studies of " + ", ".join(JSON_STUDIES)
                    + " as mfv reference studies (schema mfv-reference-1, "
                    "verify/reference_studies.hpp) for the ledger's independent check")
    args = ap.parse_args(argv)
    nys = [int(s) for s in args.ny.split(",")]
    t0 = time.time()
    if not args.no_diag:
        diagnostics(args.dmax, nys, args.traction, "default")
    if args.variant == "all":
        names = ALL
    elif args.variant == "diag":
        names = []
    else:
        names = args.variant.split(",")
        bad = [n for n in names if n not in VARIANTS]
        if bad:
            ap.error(f"unknown variant(s) {bad}; choose from {list(VARIANTS)}")
    if args.json:
        names = list(dict.fromkeys(names + list(JSON_STUDIES)))
    res = run_variants(names, args.dmax, nys, args.traction) if names else {}
    if args.json:
        write_json(args.json, res, args.dmax, args.traction)
    print(f"total time {time.time() - t0:.1f} s")


# The variants recorded for mfv's ledger, as the mfv studies they stand beside: the method as
# 001 writes it, and the two VCI orders with the boundary rules the discrete system uses.
JSON_STUDIES = {
    "default": ("kbm-si (independent)", {}),
    "vci1-cb": ("kbm-si vci=linear (independent)", {"vci": "linear"}),
    "vci2-cb": ("kbm-si vci=quadratic (independent)", {"vci": "quadratic"}),
}


def write_json(path, res, dmax, tkind):
    import json
    studies = []
    for name, (label, params) in JSON_STUDIES.items():
        if effective(name, dmax, tkind) != (2.4, "nodal"):
            sys.exit(f"--json records dmax 2.4 with the nodal traction rule, mfv's defaults")
        studies.append({
            "label": label, "method": "kbm-si", "method_params": params,
            "variant": name,
            "cases": [{"nodes": r[0], "particles": int(r[1]), "h": float(r[2]),
                       "l2_rel": float(f"{r[3]:.10g}"), "energy_rel": float(f"{r[4]:.10g}")}
                      for r in res[name]]})
    doc = {"schema": "mfv-reference-1", "generator": "tests/reference/kbm_cantilever_2d.py",
           "problem": "cantilever", "problem_params": {}, "studies": studies}
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print(f"reference studies written: {path}")


if __name__ == "__main__":
    sys.exit(main())
