"""Reference closed forms of the grain/fluid Nusselt correlations, written
independently of the C++ models (src/vansCoupling/heatTransferModels), for
the case tests and the tutorials' post-processing.

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
    f = (Res + delta) / (0.11 * Res ** 1.4 + Res + delta)
    return eps ** (-expo) * f * (0.18 * math.sqrt(Res) + 1.39) ** 2 * Pr ** alpha


def nusselt_gunn(eps, Res, Pr):
    """D.J. Gunn, Int. J. Heat Mass Transfer 21 (1978) 467-476."""
    p3 = Pr ** (1.0 / 3.0)
    return ((7 - 10 * eps + 5 * eps ** 2) * (1 + 0.7 * Res ** 0.2 * p3)
            + (1.33 - 2.4 * eps + 1.2 * eps ** 2) * Res ** 0.7 * p3)


def nusselt_ranz_marshall(eps, Res, Pr):
    """Ranz & Marshall (1952), single sphere, interstitial Re = Res/eps."""
    return 2 + 0.6 * math.sqrt(Res / eps) * Pr ** (1.0 / 3.0)


def nusselt_wakao_kaguei(Res, Pr):
    """Wakao & Kaguei (1982), packed beds, dispersion-corrected data."""
    return 2 + 1.1 * Res ** 0.6 * Pr ** (1.0 / 3.0)
