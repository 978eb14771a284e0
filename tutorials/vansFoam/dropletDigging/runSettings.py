# SPDX-License-Identifier: GPL-3.0-or-later
"""Run settings of the droplet-digging tutorial read from the environment
(Allrun's and the benches' switches): the contact solver's tolerance,
sweep cap and compliance, the vapour cohesion's persistence and strength,
the droplet's capillary barrier, vapour release, film conduction and
absorbed grains.  Each
returns the value to write into the case, or raises ValueError naming the
variable and the values it accepts.  setupCase.py loads this module and
re-exports its functions (setupCase.contact_tolerance, ...)."""

import os

# surface tension of water at 100 C [N/m]: IAPWS R1-76(2014), 58.91 mN/m
SIGMA_WATER = 0.05891


def contact_tolerance(d_grain):
    """NSCD contact tolerance (relative to d_min, src/nscd/README.md) of the
    bed: 1e-4 for the 0.5 and 1 mm beds; 1e-3 for finer beds, where the
    agitated 6000-grain bed (0.2 mm) hits maxIterations 1000 at every step
    with 1e-4 (0.5 s/step, NSCD 87 % of the time, perf) and needs 60-400
    sweeps with 1e-3 (max overlap 1.05e-3 d_min; velocity error ~1e-3
    d/dt ~ 0.7 mm/s, well below the droplet's seepage speed ~2 cm/s).
    Env CONTACT_TOL=<tol> overrides it (docs/validation/dropletDigging.md "Measured, contact-tolerance
    study"); raises ValueError if it is not a number in (0, 0.1]."""
    env = os.environ.get("CONTACT_TOL")
    if env:
        tol = float(env)
        if not 0 < tol <= 0.1:
            raise ValueError(
                f"CONTACT_TOL={env}: the contact tolerance (relative to d_min) must be in (0, 0.1]"
            )
        return tol
    return 1e-4 if d_grain >= 0.45e-3 else 1e-3


def contact_max_iterations():
    """NSCD maxIterations (sweeps per step): 1000, or env CONTACT_MAXITER
    (e.g. 3000 with CONTACT_TOL=1e-4); raises ValueError if it is not a
    positive integer."""
    n = int(os.environ.get("CONTACT_MAXITER", "1000"))
    if n < 1:
        raise ValueError(f"CONTACT_MAXITER={n}: must be a positive integer")
    return n


def contact_compliance():
    """(relativeCompliance, relaxation) of the grains' contacts (nscd
    Material::relativeCompliance, Settings::relaxation): env
    CONTACT_COMPLIANCE=<beta> (default 0: hard contacts) and
    CONTACT_RELAXATION=<omega> (default 1), e.g. 2e-3 and 1.5 to settle the
    55 um bed (docs/validation/contactCompliance.md); raises ValueError if
    beta < 0 or omega is not in (0, 2)."""
    beta = float(os.environ.get("CONTACT_COMPLIANCE", "0"))
    omega = float(os.environ.get("CONTACT_RELAXATION", "1"))
    if not beta >= 0:
        raise ValueError(f"CONTACT_COMPLIANCE={beta}: the relative contact compliance must be >= 0")
    if not 0 < omega < 2:
        raise ValueError(
            f"CONTACT_RELAXATION={omega}: the over-relaxation factor must be in (0, 2)"
        )
    return beta, omega


def contact_compliance_absolute():
    """Absolute compliance c [m^2/N per unit depth] of the grains' contacts
    (nscd Material::compliance): env CONTACT_COMPLIANCE_ABSOLUTE=<c> (default
    0: none).  Unlike relativeCompliance (c = beta W_nn dt^2), c does not
    change with the step: a bed settled at one step keeps its overlaps in a
    run whose step the droplet sets (4.5e-6 to 5e-4 s).  c must be at least
    the settle's beta W_nn dt_settle^2 of the bed's lightest pair divided by
    the run's density over the settle's (the state's impulses are scaled by
    that ratio when the porous grains replace the solid ones), or the settled
    overlaps fail the initial-overlap check: 5.5e-5 for the rain bed of
    49.5-55 um discs settled at 2e-4 s with beta 2e-3 and run with porous
    grains (1511 against 3200 kg/m^3; docs/validation/contactCompliance.md).
    Raises ValueError if c < 0 or if CONTACT_COMPLIANCE is set too (a
    material takes one of the two)."""
    c = float(os.environ.get("CONTACT_COMPLIANCE_ABSOLUTE", "0"))
    if not c >= 0:
        raise ValueError(f"CONTACT_COMPLIANCE_ABSOLUTE={c}: the contact compliance must be >= 0")
    if c > 0 and float(os.environ.get("CONTACT_COMPLIANCE", "0")) > 0:
        raise ValueError(
            "CONTACT_COMPLIANCE_ABSOLUTE and CONTACT_COMPLIANCE are both set: a material takes"
            " either the absolute or the relative compliance, unset one of them"
        )
    return c


def droplet_offset():
    """Horizontal offset [m] of the droplet's centre from the cell's
    mid-plane x = W/2 (env DROPLET_X_OFFSET, default 0): a perturbed start,
    the droplet landing on another arrangement of the grains under it, for
    the spread of the observables (depth, lift) between runs that differ
    only by where the droplet meets the bed.  Raises ValueError, naming the
    variable, if the offset is not a finite number."""
    text = os.environ.get("DROPLET_X_OFFSET", "0")
    try:
        dx = float(text)
    except ValueError:
        dx = float("nan")
    if not abs(dx) < float("inf"):
        raise ValueError(f"DROPLET_X_OFFSET={text}: the droplet offset must be a finite length [m]")
    return dx


def cohesion_settings():
    """(minAge, factor) of the grains' vapour cohesion (couplingProperties
    cohesion): minAge, the NSCD steps a contact must persist before it is
    cohesive (the thesis, section 4.3.2: cohesive once the contact "persists
    for several time steps"), env COHESION_MIN_AGE (default 5); factor, a
    multiplier of F_c^0 for the cohesion sweep (env COHESION_FACTOR, default
    1; F_c^0 must stay > 0, couplingProperties has no zero cohesion).  Raises
    ValueError if minAge < 0 or factor <= 0."""
    min_age = int(os.environ.get("COHESION_MIN_AGE", "5"))
    factor = float(os.environ.get("COHESION_FACTOR", "1"))
    if min_age < 0:
        raise ValueError(f"COHESION_MIN_AGE={min_age}: must be a non-negative number of steps")
    if not factor > 0:
        raise ValueError(f"COHESION_FACTOR={factor}: the cohesion multiplier must be > 0")
    return min_age, factor


def surface_tension(value=None):
    """Surface tension [N/m] of the droplet's capillary entry barrier
    (dropletProperties surfaceTension, src/dropletCoupling/README.md
    "Capillary entry barrier"): value if given, else env SURFACE_TENSION
    (a number, or "water" for SIGMA_WATER), else 0 (no barrier, thesis eq.
    4.17).  Raises ValueError if it is not a number >= 0."""
    if value is None:
        env = os.environ.get("SURFACE_TENSION", "")
        try:
            value = SIGMA_WATER if env == "water" else float(env or 0)
        except ValueError:
            raise ValueError(
                f"SURFACE_TENSION={env}: give the surface tension in N/m (e.g. 0.05891) or 'water'"
            ) from None
    value = float(value)
    if not value >= 0:
        raise ValueError(f"surface tension {value} N/m must be >= 0 (SURFACE_TENSION)")
    return value


def vapour_release(value=None):
    """Where the droplet's vapour leaves its surface (dropletProperties
    vapourRelease, src/dropletCoupling/vapourDroplet/vapourDroplet.H):
    value if given, else env VAPOUR_RELEASE, else "uniform" (the thesis'
    uniform blowing); "heatFlux": where the heat entered; "grains": the
    vapour of each grain's heat in the cells of that grain.  Raises
    ValueError for anything else."""
    value = value or os.environ.get("VAPOUR_RELEASE") or "uniform"
    if value not in ("uniform", "heatFlux", "grains"):
        raise ValueError(
            f"VAPOUR_RELEASE={value}: give 'uniform' (thesis, default), 'heatFlux' or 'grains'"
        )
    return value


def absorbed_grains():
    """What the grains inside the droplet are (dropletProperties
    absorbedGrains, src/dropletCoupling/README.md "The model"): env
    ABSORBED_GRAINS, else "drag" (the liquid drag law, the default);
    "carried": they move with the droplet, their mass and weight in its
    equation.  Raises ValueError for anything else."""
    value = os.environ.get("ABSORBED_GRAINS") or "drag"
    if value not in ("drag", "carried"):
        raise ValueError(f"ABSORBED_GRAINS={value}: give 'drag' (default) or 'carried'")
    return value


def liquid_conductivity():
    """Conductivity k_l [W/(m K)] with which the grains inside the droplet
    exchange heat with the liquid (dropletProperties liquidConductivity,
    src/dropletCoupling/README.md "The model"): env LIQUID_CONDUCTIVITY,
    "water" (0.679, water at 100 C, IAPWS 2011) or a value > 0; None when
    unset or "gas" (the keyword not written: as in the gas, the thesis'
    eq. 4.13).  Raises ValueError for anything else."""
    value = os.environ.get("LIQUID_CONDUCTIVITY") or "gas"
    if value == "gas":
        return None
    if value == "water":
        return 0.679
    try:
        k = float(value)
    except ValueError:
        k = float("nan")
    if not k > 0:
        raise ValueError(
            f"LIQUID_CONDUCTIVITY={value}: give 'gas' (default), 'water' or a value > 0"
        )
    return k


def yes_no(value, env_name):
    """bool(value) if value is not None, else the environment variable
    env_name, "yes" or "no" (default "no").  Raises ValueError for another
    word."""
    if value is not None:
        return bool(value)
    env = os.environ.get(env_name, "no")
    if env not in ("yes", "no"):
        raise ValueError(f"{env_name}={env}: give 'yes' or 'no'")
    return env == "yes"


def film_conduction(value=None):
    """Leidenfrost film conduction from the grains pressed on the droplet
    (dropletProperties filmConduction, vapourDroplet.H; needs the capillary
    barrier): value if given, else env FILM_CONDUCTION ("yes"/"no"), else
    False.  Raises ValueError for another word."""
    return yes_no(value, "FILM_CONDUCTION")
