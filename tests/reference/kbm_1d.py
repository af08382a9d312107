#!/usr/bin/python3
"""Independent reference implementation of 1D "EFG-KBM" (KBM si).

Purpose
-------
A self-contained numpy implementation of the Krongauz-Belytschko-corrected
Petrov-Galerkin particle method with stress-point integration, "KBM (si)" of
Rabczuk, Belytschko & Xiao, CMAME 2004, "Stable particle methods based on
Lagrangian kernels" (called 001 below).  It is written from the paper only
and shares no code with the C++ implementation under test.  Its job is to
tell whether the method, as 001 writes it, converges in 1D, and if it does
not, which ingredient is responsible.

Model problem (static, linear)
------------------------------
    -(E u')' = f  on [0, 2],  E = 1,  u = sin(3x) + x^2,  f = 9 sin(3x) - 2,
    Dirichlet u(0), u(2) at both ends.
Particles x_J = 2 J/(N-1), J = 0..N-1 (particles on the ends), dx = 2/(N-1).

Ingredients (001 equation numbers)
----------------------------------
* Kernel: cubic spline, eq (14), z = r/h on [0, 2]; rewritten with
  q = r/R, R = dmax*dx the support radius (z = 2q):
      w(q) = 1 - 6 q^2 + 6 q^3      0   <= q < 1/2
           = 2 (1 - q)^3            1/2 <= q <= 1
  (the constant C/h^D of eq (14)-(15) cancels in Shepard/MLS functions).
* Shepard functions W^S_I = W_I / sum_K W_K, eq (28) / (43), and their exact
  derivative.
* Trial functions Psi_J: MLS with linear basis p = (1, x), eqs (37)-(42).
* Trial gradient: Krongauz-Belytschko correction, eqs (26)-(32) in 1D:
      G_J(x) = a(x) dW^S_J/dx,  a(x) = 1 / sum_J dW^S_J/dx(x) x_J   (29)-(31)
  (evaluated as sum_J dW^S_J/dx (x_J - x), identical since sum_J dW^S_J/dx=0).
* Petrov-Galerkin, section 4.1.1, eqs (44)-(51): test functions Phi_I =
  Shepard, trial Psi_J = MLS with assumed gradient G_J.  Static, linear:
      K_IJ = sum_q w_q dPhi_I/dx(x_q) E G_J(x_q)         (51) with P = E u'
      f_I  = sum_q w_q Phi_I(x_q) f(x_q)                 (50)
* Stress point integration, eqs (63)-(65) and Table 1 "KBM (si)":
  quadrature points = particles + one stress point per interval midpoint,
  weights = Voronoi lengths (dx/2 interior, dx/4 at the two end particles).
* Essential BCs: Lagrange multipliers (001 sec. 3 refers to [2,17] for
  this); default saddle system [[K, Phi_b], [Psi_b^T, 0]].

Variants (--variant NAME; "all" runs every one)
------------------------------------------------
  default      KB gradient, Shepard tests, 1 stress point/interval, LM(Phi_b,Psi_b)
  bc-psi       as default, LM with Psi_b in both places
  bc-penalty   as default, penalty alpha*Phi_b (Psi_b^T u - g), alpha=1e6/dx
  gauss4/6     (a) Gauss cells, 4 or 6 points per particle interval
  nodal        (b) nodal integration only (Voronoi weights dx, dx/2 at ends)
  sp2, sp3     (c) 2 or 3 stress points per interval (equal Voronoi weights)
  vci          (d) default + VCI (Chen, Hillman & Rueter 2013) on test gradients
  vci-gauss6   (d') Gauss cells + VCI
  vci2, vci2-nodal, vci2-gauss6
               (d'') quadratic VCI (not in 001): test gradients corrected so
               the discrete weak form is exact for linear AND quadratic u
  vci2x        (d3) quadratic VCI in the divergence-identity form (the exact
               gradient x of x^2/2 in the second condition), as mfv's vci=quadratic
  mlsgrad      (e) trial gradient = full MLS derivative, Shepard tests, stress pts
  efg-sp       (f) Bubnov-Galerkin MLS/MLS, stress points
  efg-gauss4/6 (f) Bubnov-Galerkin MLS/MLS, Gauss cells

Every table also shows the linear patch test (u = a + b x, f = 0), the
largest integration-consistency residual r_I and the interior effective
modulus E_eff - E (see Discretisation.e_eff): the interior stencil of a
Shepard-test Petrov-Galerkin scheme only reproduces -E u'' if the quadrature
integrates dPhi_I x + Phi_I exactly; otherwise it approximates -E_eff u''
and the error stagnates at about |E_eff - E|.

Run:  /usr/bin/python3 tests/reference/kbm_1d.py [--variant NAME] [--dmax D]
      (default --variant all: diagnostics + every variant, ~20 s)
"""

import argparse
import sys

import numpy as np

L = 2.0               # domain [0, L]
E = 1.0               # Young's modulus
NS = [11, 21, 41, 81, 161, 321]


def u_exact(x):
    return np.sin(3 * x) + x ** 2


def du_exact(x):
    return 3 * np.cos(3 * x) + 2 * x


def f_source(x):
    return 9 * np.sin(3 * x) - 2.0


# ---------------------------------------------------------------------------
# Kernel (001 eq 14, normalised to support radius 1)
# ---------------------------------------------------------------------------
def spline(q):
    """Cubic spline w(q) and dw/dq, q = |x - x_J| / R >= 0."""
    w = np.zeros_like(q)
    dw = np.zeros_like(q)
    a = q < 0.5
    b = (q >= 0.5) & (q < 1.0)
    w[a] = 1 - 6 * q[a] ** 2 + 6 * q[a] ** 3
    dw[a] = -12 * q[a] + 18 * q[a] ** 2
    w[b] = 2 * (1 - q[b]) ** 3
    dw[b] = -6 * (1 - q[b]) ** 2
    return w, dw


def shapes(x, xp, R):
    """All shape functions at points x (n,) for particles xp (N,), radius R.

    Returns dict of (n, N) arrays:
      W, dW     kernel and its x-derivative
      S, dS     Shepard function (eq 28) and exact derivative
      G         Krongauz-Belytschko corrected derivative (eqs 27-32, 1D)
      Psi, dPsi linear MLS function (eqs 38-42) and its exact derivative
    """
    r = x[:, None] - xp[None, :]
    q = np.abs(r) / R
    W, dwq = spline(q)
    dW = dwq * np.sign(r) / R

    # Shepard, eq (28):  S = W / sum W;  dS = (dW - S sum dW) / sum W
    sW = W.sum(axis=1, keepdims=True)
    sdW = dW.sum(axis=1, keepdims=True)
    S = W / sW
    dS = (dW - S * sdW) / sW

    # KB correction, eqs (29)-(32): a = 1 / sum_J dS_J x_J  (1x1 "A" of eq 31)
    # sum_J dS_J = 0 exactly, so sum_J dS_J x_J = sum_J dS_J (x_J - x).
    Akb = (dS * (xp[None, :] - x[:, None])).sum(axis=1, keepdims=True)
    G = dS / Akb

    # MLS, eqs (38)-(42), basis p(y) = (1, (y - x0)/R) with x0 frozen at the
    # evaluation point (a shifted/scaled copy of p = (1, x); same Psi).
    # p(x) = (1, 0), dp/dx = (0, 1/R), p_J = (1, s_J), s_J = (x_J - x)/R.
    s = -r / R
    A00, A01, A11 = W.sum(1), (W * s).sum(1), (W * s * s).sum(1)
    dA00, dA01, dA11 = dW.sum(1), (dW * s).sum(1), (dW * s * s).sum(1)
    det = A00 * A11 - A01 ** 2
    # gamma = A^{-1} p(x),  p(x) = (1, 0)
    g0, g1 = A11 / det, -A01 / det
    # dgamma = A^{-1} (dp - dA gamma)
    b0 = 0.0 - (dA00 * g0 + dA01 * g1)
    b1 = 1.0 / R - (dA01 * g0 + dA11 * g1)
    dg0 = (A11 * b0 - A01 * b1) / det
    dg1 = (-A01 * b0 + A00 * b1) / det
    gp = g0[:, None] + g1[:, None] * s          # gamma . p_J
    dgp = dg0[:, None] + dg1[:, None] * s       # dgamma . p_J
    Psi = W * gp
    dPsi = dW * gp + W * dgp
    return dict(W=W, dW=dW, S=S, dS=dS, G=G, Psi=Psi, dPsi=dPsi)


# ---------------------------------------------------------------------------
# Quadrature rules
# ---------------------------------------------------------------------------
def rule_stress(N, nsp):
    """Particles + nsp equally spaced stress points per interval, Voronoi
    weights (eqs 63-65).  nsp=0 is nodal integration (eq 59)."""
    dx = L / (N - 1)
    h = dx / (nsp + 1)
    n = (N - 1) * (nsp + 1) + 1
    xq = np.linspace(0.0, L, n)
    wq = np.full(n, h)
    wq[0] = wq[-1] = h / 2
    return xq, wq


def rule_gauss(N, ng, nsub=1):
    """ng-point Gauss rule on each of nsub*(N-1) equal cells (eqs 66-69, 1D)."""
    xi, wi = np.polynomial.legendre.leggauss(ng)
    edges = np.linspace(0.0, L, nsub * (N - 1) + 1)
    a, b = edges[:-1, None], edges[1:, None]
    xq = (0.5 * (a + b) + 0.5 * (b - a) * xi[None, :]).ravel()
    wq = (0.5 * (b - a) * wi[None, :]).ravel()
    return xq, wq


# ---------------------------------------------------------------------------
# Method definition
# ---------------------------------------------------------------------------
VARIANTS = {
    # name: (test, trial-gradient, quadrature, bc, vci, description)
    "default":    ("shepard", "kb",  ("sp", 1), "lm-phi", 0,
                   "KBM si: KB grad, Shepard test, 1 SP/interval, LM [[K,Phi_b],[Psi_b^T,0]]"),
    "bc-psi":     ("shepard", "kb",  ("sp", 1), "lm-psi", 0,
                   "as default, LM [[K,Psi_b],[Psi_b^T,0]]"),
    "bc-penalty": ("shepard", "kb",  ("sp", 1), "penalty", 0,
                   "as default, penalty alpha Phi_b(Psi_b^T u - g), alpha=1e6/dx"),
    "gauss4":     ("shepard", "kb",  ("gauss", 4), "lm-phi", 0,
                   "(a) KB/Shepard, 4-pt Gauss per interval"),
    "gauss6":     ("shepard", "kb",  ("gauss", 6), "lm-phi", 0,
                   "(a) KB/Shepard, 6-pt Gauss per interval"),
    "nodal":      ("shepard", "kb",  ("sp", 0), "lm-phi", 0,
                   "(b) KB/Shepard, nodal integration"),
    "sp2":        ("shepard", "kb",  ("sp", 2), "lm-phi", 0,
                   "(c) KB/Shepard, 2 SP/interval"),
    "sp3":        ("shepard", "kb",  ("sp", 3), "lm-phi", 0,
                   "(c) KB/Shepard, 3 SP/interval"),
    "vci":        ("shepard", "kb",  ("sp", 1), "lm-phi", 1,
                   "(d) default + VCI on test gradients"),
    "vci-gauss6": ("shepard", "kb",  ("gauss", 6), "lm-phi", 1,
                   "(d') KB/Shepard, 6-pt Gauss + VCI"),
    "vci2":       ("shepard", "kb",  ("sp", 1), "lm-phi", 2,
                   "(d'') default + quadratic (2nd-order) VCI on test gradients"),
    "vci2x":      ("shepard", "kb",  ("sp", 1), "lm-phi", 3,
                   "(d3) default + quadratic VCI, divergence form sum w (dPhi x + Phi) = [Phi x]"),
    "vci2-nodal": ("shepard", "kb",  ("sp", 0), "lm-phi", 2,
                   "(d'') nodal integration + quadratic VCI"),
    "vci2-gauss6": ("shepard", "kb", ("gauss", 6), "lm-phi", 2,
                   "(d'') 6-pt Gauss + quadratic VCI"),
    "mlsgrad":    ("shepard", "mls", ("sp", 1), "lm-phi", 0,
                   "(e) MLS derivative as trial grad, Shepard test, 1 SP/interval"),
    "efg-sp":     ("mls", "mls", ("sp", 1), "lm-phi", 0,
                   "(f) Bubnov-Galerkin MLS/MLS, 1 SP/interval"),
    "efg-gauss4": ("mls", "mls", ("gauss", 4), "lm-phi", 0,
                   "(f) Bubnov-Galerkin MLS/MLS, 4-pt Gauss per interval"),
    "efg-gauss6": ("mls", "mls", ("gauss", 6), "lm-phi", 0,
                   "(f) Bubnov-Galerkin MLS/MLS, 6-pt Gauss per interval"),
}


def trial_grad(sh, kind):
    return sh["G"] if kind == "kb" else sh["dPsi"]


def test_fun(sh, kind):
    return (sh["S"], sh["dS"]) if kind == "shepard" else (sh["Psi"], sh["dPsi"])


class Discretisation:
    """Assembled system for one variant and one N."""

    def __init__(self, N, dmax, variant):
        self.N = N
        self.dx = L / (N - 1)
        self.R = dmax * self.dx
        self.xp = np.linspace(0.0, L, N)
        (self.test, self.grad, quad, self.bc, self.vci, _) = VARIANTS[variant]
        if quad[0] == "sp":
            self.xq, self.wq = rule_stress(N, quad[1])
        else:
            self.xq, self.wq = rule_gauss(N, quad[1])

        shq = shapes(self.xq, self.xp, self.R)
        self.shq = shq
        T, dT = test_fun(shq, self.test)
        Gt = trial_grad(shq, self.grad)

        # boundary values of test and trial functions at x = 0 and x = L
        shb = shapes(np.array([0.0, L]), self.xp, self.R)
        self.Tb, _ = test_fun(shb, self.test)        # (2, N)
        self.Pb = shb["Psi"]                          # (2, N)

        # integration-consistency residual of the test gradients:
        # r_I = sum_q w_q dPhi_I(x_q) - (Phi_I(L) - Phi_I(0))
        bterm = self.Tb[1] - self.Tb[0]
        self.r_raw = dT.T @ self.wq - bterm
        insupp = (shq["W"] > 0).astype(float)      # x_q in supp(Phi_I)
        if self.vci == 1:
            # VCI (Chen, Hillman & Rueter 2013), linear: dPhi_I += c_I on
            # supp(I) so that sum_q w_q dPhi_I = Phi_I(L) - Phi_I(0).
            c = -self.r_raw / (insupp.T @ self.wq)
            dT = dT + insupp * c[None, :]
        elif self.vci in (2, 3):
            # Quadratic VCI (not in 001; diagnostic): dPhi_I += c0_I +
            # c1_I (x - x_I)/dx on supp(I), chosen so that the discrete weak
            # form is exact for u = 1 + x and for u = x^2/2 with the method's
            # own gradient g = sum_J G_J x_J^2/2 and exact boundary fluxes:
            #   sum_q w dPhi_I          = [Phi_I]_0^L
            #   sum_q w dPhi_I g(x_q)   = [Phi_I x]_0^L - sum_q w Phi_I
            # vci 3 (vci2x): the second divergence identity of Chen, Hillman & Rueter
            # (2013), sum_q w (dPhi_I x_q + Phi_I) = [Phi_I x]_0^L: the exact gradient x of
            # x^2/2 in place of the method's discrete one.
            g1 = Gt @ (self.xp ** 2 / 2) if self.vci == 2 else self.xq.copy()
            t0 = bterm
            t1 = self.Tb[1] * L - self.wq @ T
            r0 = dT.T @ self.wq - t0
            r1 = dT.T @ (self.wq * g1) - t1
            h1 = (self.xq[:, None] - self.xp[None, :]) / self.dx
            wI = self.wq[:, None] * insupp
            m00 = wI.sum(0)
            m01 = (wI * h1).sum(0)
            m10 = (wI * g1[:, None]).sum(0)
            m11 = (wI * g1[:, None] * h1).sum(0)
            det = m00 * m11 - m01 * m10
            c0 = (-r0 * m11 + r1 * m01) / det
            c1 = (-r1 * m00 + r0 * m10) / det
            dT = dT + insupp * (c0[None, :] + c1[None, :] * h1)
        self.r = dT.T @ self.wq - bterm

        # eq (51) / (64): K_IJ = sum_q w_q dPhi_I(x_q) E G_J(x_q)
        self.K = dT.T @ (self.wq[:, None] * E * Gt)
        self.T = T
        self.dT = dT
        self.Gt = Gt

    def e_eff(self):
        """Interior second-order consistency: apply the stiffness row of a
        mid-domain test function to nodal values x_J^2/2 (u'' = 1) and divide
        by its load for f = -u'' = -1.  A consistent scheme gives E_eff = E;
        E_eff != E means the interior stencil approximates -E_eff u'' = f,
        i.e. the scheme converges (at best) to the wrong solution."""
        I = self.N // 2
        return -(self.K[I] @ (self.xp ** 2 / 2)) / (self.wq @ self.T[:, I])

    def solve(self, fq_fun, g):
        """Solve with load f(x) and Dirichlet data g = (u(0), u(L))."""
        N = self.N
        fvec = self.T.T @ (self.wq * fq_fun(self.xq))       # eq (50)
        g = np.asarray(g, float)
        if self.bc in ("lm-phi", "lm-psi"):
            B = self.Tb if self.bc == "lm-phi" else self.Pb
            M = np.zeros((N + 2, N + 2))
            M[:N, :N] = self.K
            M[:N, N:] = B.T           # multiplier enters test equation I
            M[N:, :N] = self.Pb       # constraint on trial functions
            rhs = np.concatenate([fvec, g])
            sol = np.linalg.solve(M, rhs)
            return sol[:N]
        # penalty: alpha * sum_b Phi_I(x_b) (sum_J Psi_J(x_b) u_J - g_b)
        alpha = 1e6 * E / self.dx
        M = self.K + alpha * self.Tb.T @ self.Pb
        rhs = fvec + alpha * self.Tb.T @ g
        return np.linalg.solve(M, rhs)


# ---------------------------------------------------------------------------
# Error norms with a fine Gauss rule (10 points on each of 4(N-1) cells)
# ---------------------------------------------------------------------------
def errors(disc, uJ, uex, duex, chunk=4000):
    xf, wf = rule_gauss(disc.N, 10, nsub=4)
    eL2 = eH1 = eH1m = 0.0
    egmax = 0.0
    for i in range(0, xf.size, chunk):
        x, w = xf[i:i + chunk], wf[i:i + chunk]
        sh = shapes(x, disc.xp, disc.R)
        uh = sh["Psi"] @ uJ
        gh = trial_grad(sh, disc.grad) @ uJ      # the method's gradient
        gm = sh["dPsi"] @ uJ                     # MLS derivative
        eL2 += np.sum(w * (uh - uex(x)) ** 2)
        eH1 += np.sum(w * (gh - duex(x)) ** 2)
        eH1m += np.sum(w * (gm - duex(x)) ** 2)
        egmax = max(egmax, np.max(np.abs(gh - duex(x))))
    shp = shapes(disc.xp, disc.xp, disc.R)
    enod = np.max(np.abs(shp["Psi"] @ uJ - uex(disc.xp)))
    return np.sqrt(eL2), np.sqrt(eH1), np.sqrt(eH1m), enod, egmax


def rates(dxs, es):
    dxs, es = np.asarray(dxs), np.asarray(es)
    pair = np.log(es[:-1] / es[1:]) / np.log(dxs[:-1] / dxs[1:])
    ls = np.polyfit(np.log(dxs), np.log(es), 1)[0]
    return pair, ls


def run_variant(name, dmax, Ns=NS):
    print("=" * 96)
    print(f"variant {name}: {VARIANTS[name][5]}   (dmax = {dmax})")
    print("=" * 96)
    rows = []
    for N in Ns:
        d = Discretisation(N, dmax, name)
        uJ = d.solve(f_source, (u_exact(0.0), u_exact(L)))
        eL2, eH1, eH1m, enod, _ = errors(d, uJ, u_exact, du_exact)
        # linear patch test u = a + b x, f = 0
        a, b = 0.3, 1.7
        up = d.solve(lambda x: 0.0 * x, (a, a + b * L))
        _, _, _, pnod, pgrad = errors(d, up, lambda x: a + b * x,
                                      lambda x: b + 0.0 * x)
        rows.append((N, d.dx, eL2, eH1, eH1m, enod, pnod, pgrad,
                     np.max(np.abs(d.r)), d.e_eff() - E))
    dxs = [r[1] for r in rows]
    cols = {"L2": 2, "H1(method grad)": 3, "H1(MLS deriv)": 4, "nodal max": 5}
    print(f"{'N':>5} {'L2':>11} {'rate':>6} {'H1(G)':>11} {'rate':>6} "
          f"{'H1(dPsi)':>11} {'rate':>6} {'nodal':>11} {'rate':>6} | "
          f"{'patch nod':>9} {'patch grad':>10} {'max|r_I|':>9} {'Eeff-E':>9}")
    pr = {k: rates(dxs, [r[c] for r in rows]) for k, c in cols.items()}
    for i, r in enumerate(rows):
        def rt(k):
            return "" if i == 0 else f"{pr[k][0][i - 1]:6.2f}"
        print(f"{r[0]:5d} {r[2]:11.4e} {rt('L2'):>6} {r[3]:11.4e} "
              f"{rt('H1(method grad)'):>6} {r[4]:11.4e} {rt('H1(MLS deriv)'):>6} "
              f"{r[5]:11.4e} {rt('nodal max'):>6} | {r[6]:9.2e} {r[7]:10.2e} "
              f"{r[8]:9.2e} {r[9]:+9.2e}")
    print("least-squares rates: " + ", ".join(
        f"{k} {v[1]:.2f}" for k, v in pr.items()))
    print()
    return rows


def diagnostics(dmax, name="default"):
    """Patch-test diagnostics for a variant:
    (1) linear patch test u = a + b x, f = 0: max nodal error
        |sum_K Psi_K(x_J) u_K - u(x_J)| and max gradient error |sum G_J u_J - b|
    (2) integration consistency r_I = sum_q w_q dPhi_I(x_q) - [Phi_I]_0^L,
        max over interior and boundary-near I (and r/dx, the ratio to f_I)
    (3) |sum_q w_q - L|
    (4) max_q |sum_J G_J x_J - 1| and max_q |sum_J G_J| * dx
    (5) interior second-order consistency E_eff - E (see e_eff())."""
    print("=" * 96)
    print(f"patch-test diagnostics, variant {name} (dmax = {dmax})")
    print("=" * 96)
    print(f"{'N':>5} {'(1)nodal':>10} {'(1)grad':>10} {'(2)r int':>10} "
          f"{'(2)r bnd':>10} {'(2)r bnd/dx':>11} {'(3)sum w-2':>10} "
          f"{'(4)|Gx-1|':>10} {'(4)|sumG|*dx':>12} {'(5)Eeff-E':>10}")
    for N in NS:
        d = Discretisation(N, dmax, name)
        a, b = 0.3, 1.7
        up = d.solve(lambda x: 0.0 * x, (a, a + b * L))
        _, _, _, pnod, pgrad = errors(d, up, lambda x: a + b * x,
                                      lambda x: b + 0.0 * x)
        # "boundary-near" test functions: Phi_I is affected by the boundary
        # (a Shepard/MLS function sees all particles within R of its support,
        # so this is |x_I - x_b| < 2R); the rest are "interior".
        bnd = (d.xp < 2 * d.R) | (d.xp > L - 2 * d.R)
        rint = np.max(np.abs(d.r[~bnd])) if np.any(~bnd) else 0.0
        rbnd = np.max(np.abs(d.r[bnd]))
        sw = abs(d.wq.sum() - L)
        G = d.shq["G"]
        gx = np.max(np.abs(G @ d.xp - 1.0))
        g0 = np.max(np.abs(G.sum(axis=1))) * d.dx
        print(f"{N:5d} {pnod:10.2e} {pgrad:10.2e} {rint:10.2e} {rbnd:10.2e} "
              f"{rbnd / d.dx:11.2e} {sw:10.2e} {gx:10.2e} {g0:12.2e} "
              f"{d.e_eff() - E:+10.2e}")
    # detail: residual per test function near x = 0 at the finest N
    d = Discretisation(NS[-1], dmax, name)
    k = int(np.ceil(dmax)) + 2
    print(f"r_I (raw, before any VCI) for I = 0..{k - 1} at N = {NS[-1]}: "
          + " ".join(f"{v:+.3e}" for v in d.r_raw[:k]))
    d = Discretisation(NS[1], dmax, name)
    print(f"r_I (raw) for I = 0..{k - 1} at N = {NS[1]}:  "
          + " ".join(f"{v:+.3e}" for v in d.r_raw[:k]))
    print()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--variant", default="all",
                    choices=["all"] + list(VARIANTS))
    ap.add_argument("--dmax", type=float, default=2.4)
    ap.add_argument("--no-diag", action="store_true",
                    help="skip the patch-test diagnostics")
    ap.add_argument("--json", metavar="FILE",
                    help="only write the studies of " + ", ".join(JSON_STUDIES)
                    + " as mfv reference studies (schema mfv-reference-1, "
                    "verify/reference_studies.hpp)")
    args = ap.parse_args(argv)
    if args.json:
        write_json(args.json, args.dmax)
        return 0
    names = list(VARIANTS) if args.variant == "all" else [args.variant]
    np.set_printoptions(linewidth=120)
    if not args.no_diag:
        diagnostics(args.dmax, "default")
        for extra in ("vci", "vci2"):
            if extra in names:
                diagnostics(args.dmax, extra)
    for n in names:
        run_variant(n, args.dmax)


# The variants recorded for mfv, as the mfv studies they stand beside (problem mms-poisson-1d).
JSON_STUDIES = {
    "default": ("kbm-si (independent)", {}),
    "vci": ("kbm-si vci=linear (independent)", {"vci": "linear"}),
    "vci2x": ("kbm-si vci=quadratic (independent)", {"vci": "quadratic"}),
}


def write_json(path, dmax):
    """Relative L2 and H1-seminorm errors (the H1 one of the MLS derivative, as mfv's common
    rule measures it) of the recorded variants at NS."""
    import json
    xf, wf = rule_gauss(NS[-1], 10, nsub=4)
    norm_u = np.sqrt(np.sum(wf * u_exact(xf) ** 2))
    norm_du = np.sqrt(np.sum(wf * du_exact(xf) ** 2))
    studies = []
    for name, (label, params) in JSON_STUDIES.items():
        cases = []
        for N in NS:
            d = Discretisation(N, dmax, name)
            uJ = d.solve(f_source, (u_exact(0.0), u_exact(L)))
            eL2, _, eH1m, _, _ = errors(d, uJ, u_exact, du_exact)
            cases.append({"nodes": N, "particles": N, "h": float(d.dx),
                          "l2_rel": float(f"{eL2 / norm_u:.10g}"),
                          "h1_semi_rel": float(f"{eH1m / norm_du:.10g}")})
        if dmax != 2.4:
            params = dict(params, dmax=dmax)
        studies.append({"label": label, "method": "kbm-si", "method_params": params,
                        "variant": name, "cases": cases})
    doc = {"schema": "mfv-reference-1", "generator": "tests/reference/kbm_1d.py",
           "problem": "mms-poisson-1d", "problem_params": {}, "studies": studies}
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print(f"reference studies written: {path}")


if __name__ == "__main__":
    sys.exit(main())
