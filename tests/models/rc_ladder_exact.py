"""Closed-form solution of the SciMLBenchmarks RC ladder
(tests/models/rc_circuit_sciml.lsd), standard library only.

Node k (capacitor k) has voltage u_k; resistor k joins node k-1 to node k,
node 0 is the source V sin(w t). With conductances G_k = 1/R_k:
    C_k u_k' = G_k (u_{k-1} - u_k) - G_{k+1} (u_k - u_{k+1}),
a linear system u' = A u + b sin(w t) with A = C^-1 K, K symmetric. So
    u(t) = exp(A t) (u(0) - Im z) + Im(z e^{i w t}),  (i w - A) z = b,
and exp(A t) = C^-1/2 Q exp(L t) Q' C^1/2 from the eigen-decomposition
S = C^-1/2 K C^-1/2 = Q L Q' (Jacobi rotations: S is symmetric).
"""
import cmath
import math


def ladder(n):
    """K (symmetric, tridiagonal), b and C of the ladder of n sections:
    R_k = 1/k, C_k = 1/k^2, as in SciMLBenchmarks."""
    g = [float(k) for k in range(1, n + 2)]  # G_k = 1/R_k = k; g[n] unused
    K = [[0.0] * n for _ in range(n)]
    for k in range(n):
        K[k][k] = -g[k] - (g[k + 1] if k + 1 < n else 0.0)
        if k + 1 < n:
            K[k][k + 1] = K[k + 1][k] = g[k + 1]
    b = [0.0] * n
    b[0] = g[0]
    C = [1.0 / (k * k) for k in range(1, n + 1)]
    return K, b, C


def jacobi_eigen(S):
    """Eigenvalues and eigenvectors (columns of Q) of a symmetric S."""
    n = len(S)
    A = [row[:] for row in S]
    Q = [[float(i == j) for j in range(n)] for i in range(n)]
    for _ in range(100):
        off = sum(A[i][j] ** 2 for i in range(n) for j in range(n) if i != j)
        if off <= 1e-30 * sum(A[i][i] ** 2 for i in range(n)):
            break
        for p in range(n - 1):
            for q in range(p + 1, n):
                if A[p][q] == 0.0:
                    continue
                theta = (A[q][q] - A[p][p]) / (2 * A[p][q])
                t = math.copysign(1.0, theta) / (abs(theta) +
                                                 math.sqrt(theta ** 2 + 1))
                c = 1 / math.sqrt(t * t + 1)
                s = t * c
                for k in range(n):  # A <- A J
                    akp, akq = A[k][p], A[k][q]
                    A[k][p], A[k][q] = c * akp - s * akq, s * akp + c * akq
                for k in range(n):  # A <- J' A
                    apk, aqk = A[p][k], A[q][k]
                    A[p][k], A[q][k] = c * apk - s * aqk, s * apk + c * aqk
                for k in range(n):
                    qkp, qkq = Q[k][p], Q[k][q]
                    Q[k][p], Q[k][q] = c * qkp - s * qkq, s * qkp + c * qkq
    return [A[i][i] for i in range(n)], Q


def solve_complex(M, rhs):
    """Gaussian elimination with partial pivoting."""
    n = len(M)
    A = [row[:] + [rhs[i]] for i, row in enumerate(M)]
    for col in range(n):
        piv = max(range(col, n), key=lambda r: abs(A[r][col]))
        A[col], A[piv] = A[piv], A[col]
        for r in range(col + 1, n):
            f = A[r][col] / A[col][col]
            for c in range(col, n + 1):
                A[r][c] -= f * A[col][c]
    x = [0j] * n
    for r in range(n - 1, -1, -1):
        x[r] = (A[r][n] - sum(A[r][c] * x[c] for c in range(r + 1, n))) / \
            A[r][r]
    return x


def solution(n, t, freq=10.0, amplitude=1.0):
    """u_k(t), k = 1..n, from u_k(0) = k."""
    K, b, C = ladder(n)
    w = 2 * math.pi * freq
    A = [[K[i][j] / C[i] for j in range(n)] for i in range(n)]
    bA = [amplitude * b[i] / C[i] for i in range(n)]
    z = solve_complex([[(1j * w if i == j else 0) - A[i][j] for j in range(n)]
                       for i in range(n)], bA)
    sq = [math.sqrt(c) for c in C]
    S = [[K[i][j] / (sq[i] * sq[j]) for j in range(n)] for i in range(n)]
    lam, Q = jacobi_eigen(S)
    u0 = [float(k) for k in range(1, n + 1)]
    d0 = [sq[i] * (u0[i] - z[i].imag) for i in range(n)]  # C^1/2 (u0 - Im z)
    coef = [sum(Q[i][m] * d0[i] for i in range(n)) * math.exp(lam[m] * t)
            for m in range(n)]
    e = cmath.exp(1j * w * t)
    return [sum(Q[i][m] * coef[m] for m in range(n)) / sq[i] + (z[i] * e).imag
            for i in range(n)]
