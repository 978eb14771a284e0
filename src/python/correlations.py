# SPDX-License-Identifier: GPL-3.0-or-later
"""Reference closed forms of the grain/fluid closures, written independently
of the C++ models (src/vansCoupling/heatTransferModels, dragModels), for the
case tests and the tutorials' post-processing.

Drag: the coded laws (gamma_*, per unit grain volume, interstitial Re; used
by consistency checks and post-processing only) and independent references
(the standard drag curve, Ergun, Richardson-Zaki exponents).

Nusselt numbers:

All take the superficial Reynolds number Res = eps |u - v| d / nu
(= eps Re, Re the interstitial one), the void fraction eps and the Prandtl
number Pr, and return Nu = h d / k.
"""

import math


def nusselt_difelice_colburn(eps, Res, Pr, delta=500.0, alpha=0.4):
    """Thesis eq. 4.12: g(eps, Res) f(Res) (0.18 sqrt(Res) + 1.39)^2 Pr^alpha,
    f of eq. 4.9 (delta = 500), g of eq. 4.10 (log base 10, as the drag of
    eq. 3.32); at Res = 0 the exponent of g is 1.8."""
    expo = 1.8 - math.exp(-0.5 * (1.5 - math.log10(Res)) ** 2) if Res > 0 else 1.8
    f = (Res + delta) / (0.11 * Res**1.4 + Res + delta)
    return eps ** (-expo) * f * (0.18 * math.sqrt(Res) + 1.39) ** 2 * Pr**alpha


def nusselt_gunn(eps, Res, Pr):
    """D.J. Gunn, Int. J. Heat Mass Transfer 21 (1978) 467-476."""
    p3 = Pr ** (1.0 / 3.0)
    return (7 - 10 * eps + 5 * eps**2) * (1 + 0.7 * Res**0.2 * p3) + (
        1.33 - 2.4 * eps + 1.2 * eps**2
    ) * Res**0.7 * p3


def nusselt_ranz_marshall(eps, Res, Pr):
    """Ranz & Marshall (1952), single sphere, interstitial Re = Res/eps."""
    return 2 + 0.6 * math.sqrt(Res / eps) * Pr ** (1.0 / 3.0)


def nusselt_wakao_kaguei(Res, Pr):
    """Wakao & Kaguei (1982), packed beds, dispersion-corrected data."""
    return 2 + 1.1 * Res**0.6 * Pr ** (1.0 / 3.0)


# -- drag ---------------------------------------------------------------------
G = 9.81
DISC_PER_UNIT_DEPTH = 8.0 / (3.0 * math.pi)  # gamma_disc / gamma_sphere


def cd_dallavalle(Re):
    """Dallavalle (1948) single-sphere drag coefficient."""
    return (0.63 + 4.8 / math.sqrt(Re)) ** 2


def cd_brown_lawler(Re):
    """Standard drag curve of a sphere, Brown & Lawler (2003, J. Environ. Eng.
    129, 222-231, eq. 19; a fit of 480 measurements, Re < 2e5)."""
    return 24.0 / Re * (1 + 0.150 * Re**0.681) + 0.407 / (1 + 8710.0 / Re)


def gamma_dallavalle_difelice(eps, Re, d, mu):
    """Di Felice (1994) published form with Dallavalle's C_d0, per unit
    sphere volume: 0.75 (0.63 sqrt(Res) + 4.8)^2 eps^(1 - chi) mu/d^2,
    chi = 3.7 - 0.65 exp(-(1.5 - log10 Res)^2/2), Res = eps Re."""
    Res = max(eps * Re, 1e-12)
    chi = 3.7 - 0.65 * math.exp(-0.5 * (1.5 - math.log10(Res)) ** 2)
    return 0.75 * (0.63 * math.sqrt(Res) + 4.8) ** 2 * eps ** (1 - chi) * mu / d**2


def gamma_thesis_eq332(eps, Re, d, mu):
    """Thesis eq. 3.32 as printed, exponent of eq. 4.10 plus 1 (the
    twoDimensionalDrag thesisEq3.32 convention)."""
    er = max(eps * Re, 1e-12)
    x = 2.8 - math.exp(-0.5 * (1.5 - math.log10(er)) ** 2)
    return eps**-x * (0.77 * math.sqrt(er) + 5.88) ** 2 * mu / d**2


def gamma_gidaspow(eps, Re, d, mu, rho):
    """Gidaspow (1994): Ergun below eps 0.8, Wen & Yu above."""
    slip = Re * mu / (rho * d)
    if eps < 0.8:
        return 150 * (1 - eps) * mu / (eps * d * d) + 1.75 * rho * slip / d
    er = eps * Re
    if er < 1000:
        return 18 * mu / d**2 * (1 + 0.15 * er**0.687) * eps**-2.65
    return 0.75 * 0.44 * eps * rho * slip * eps**-2.65 / d


def terminal_velocity(cd, d, nu, rho, rhop, g=G):
    """Terminal slip w of a lone sphere: (rho_p - rho) g pi d^3/6 =
    1/2 rho C_d(w d/nu) pi d^2/4 w^2, by bisection on log w."""
    lo, hi = 1e-9, 10.0
    for _ in range(200):
        w = math.sqrt(lo * hi)
        f = (rhop - rho) * g * d / (0.75 * rho * cd(w * d / nu)) - w * w
        lo, hi = (w, hi) if f > 0 else (lo, w)
    return w


def faxen_cylinder_drag(k, viscosity_ratio=math.inf):
    """Drag per unit length / (mu U) of a circular cylinder of diameter D
    moving midway between plane walls H apart, k = D/H < 0.5, Stokes flow.
    Solid cylinder (viscosity_ratio inf): Faxen (1946) (Happel & Brenner
    1965; Ben Richou et al. 2004 eq. 1).  Fluid cylinder of viscosity ratio
    lambda without surface tension (a 2D drop): the inner Stokes solution
    outside a circle, f(r) sin(theta) with f = C (r ln(r/a) + B r - B a^2/r),
    gives B = -1/2 for the solid (no slip) and, with the inner flow and the
    continuity of tangential velocity and stress, B = -lambda / (2 (1 +
    lambda)) for the drop (the 2D Hadamard-Rybczynski); Faxen's constant
    -0.9157 = -1/2 - 0.4157 becomes -0.4157 + B.  The walls' k^2 .. k^8 terms
    are the solid's (the drop's dipole is weaker: an approximation of a few
    per cent of the sum at k = 1/6)."""
    lam = viscosity_ratio
    b = -0.5 if math.isinf(lam) else -lam / (2 * (1 + lam))
    walls = 1.7244 * k**2 - 1.7302 * k**4 + 2.4056 * k**6 - 4.5913 * k**8
    return 4 * math.pi / (-math.log(k) - 0.4157 + b + walls)


def hadamard_rybczynski_velocity(drho, radius, mu, viscosity_ratio=1.0, g=G):
    """Terminal velocity of a 3D drop of radius a in an unbounded fluid,
    Stokes flow, no surface tension: 2/3 drho g a^2 / mu (1 + lambda) /
    (2 + 3 lambda) (Hadamard 1911, Rybczynski 1911)."""
    lam = viscosity_ratio
    return 2 / 3 * drho * g * radius**2 / mu * (1 + lam) / (2 + 3 * lam)


def ergun_gradient(eps, Us, d, mu, rho):
    """Ergun (1952) pressure gradient [Pa/m] at superficial velocity Us."""
    return 150 * mu * (1 - eps) ** 2 * Us / (eps**3 * d**2) + 1.75 * rho * (1 - eps) * Us**2 / (
        eps**3 * d
    )


def n_richardson_zaki(Ret):
    """Richardson & Zaki (1954, Chem. Eng. Sci. 3, 65-73) exponent of
    U/v_t = eps^n, unbounded suspension (d/D -> 0)."""
    if Ret < 0.2:
        return 4.65
    if Ret < 1:
        return 4.4 * Ret**-0.03
    if Ret < 500:
        return 4.4 * Ret**-0.1
    return 2.39


def n_garside_al_dibouni(Ret):
    """Garside & Al-Dibouni (1977, Ind. Eng. Chem. Process Des. Dev. 16,
    206-214) exponent of U/v_t = eps^n."""
    return (5.1 + 0.27 * Ret**0.9) / (1 + 0.1 * Ret**0.9)
