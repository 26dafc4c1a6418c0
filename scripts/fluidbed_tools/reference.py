"""Reference values the tests and studies compare against, each written once: the analytic linear spring-dashpot
contact (seed eq. 2.3, 3.2-3.3), the drag correlations of the seed's Ergun/Wen-Yu law (eq. 2.11-2.17, as
include/fluidbed/kernels/drag_*.hpp), Ergun's packed-bed pressure gradient and the minimum fluidization velocity it
gives, the terminal velocity of a drag law, and plane Poiseuille flow. SI units throughout."""
import math

# ---------------------------------------------------------------------------------------------------------------
# The linear spring-dashpot contact (DEM)


def damping_ratio(e):
    """Seed eq. 3.3: gamma = -ln e / sqrt(pi^2 + ln^2 e)."""
    le = math.log(e)
    return -le / math.sqrt(math.pi ** 2 + le ** 2)


def contact_time(kn, e, m_eff):
    """Seed eq. 3.2: duration of a linear spring-dashpot contact without external force."""
    g = damping_ratio(e)
    return math.pi / math.sqrt(kn * (1.0 - g * g) / m_eff)


def wall_contact(v_in, kn, e, m, g):
    """A sphere hits a horizontal wall at speed v_in under gravity g; the wall is a linear spring-dashpot with
    m_eff = m. The overlap d(t) obeys m d'' = -kn d - eta d' + m g with d(0) = 0, d'(0) = v_in; the contact ends at
    the first return to d = 0. Returns (exit speed, contact duration)."""
    w0 = math.sqrt(kn / m)
    gam = damping_ratio(e)
    wd = w0 * math.sqrt(1.0 - gam * gam)
    ds = m * g / kn  # static overlap under gravity
    A = -ds
    B = (v_in + gam * w0 * A) / wd

    def d(t):
        return ds + math.exp(-gam * w0 * t) * (A * math.cos(wd * t) + B * math.sin(wd * t))

    def dd(t):
        ex = math.exp(-gam * w0 * t)
        c, s = math.cos(wd * t), math.sin(wd * t)
        return ex * (-gam * w0 * (A * c + B * s) + wd * (-A * s + B * c))

    # the overlap is positive on (0, t_end); bracket the root after the maximum by stepping forward
    t_lo = 0.25 * math.pi / wd
    step = 0.05 * math.pi / wd
    t_hi = t_lo
    while d(t_hi) > 0.0:
        t_lo = t_hi
        t_hi += step
        if t_hi > 10 * math.pi / wd:
            raise RuntimeError("the particle does not leave the wall (resting contact)")
    for _ in range(200):
        t_mid = 0.5 * (t_lo + t_hi)
        if d(t_mid) > 0.0:
            t_lo = t_mid
        else:
            t_hi = t_mid
    t_end = 0.5 * (t_lo + t_hi)
    return -dd(t_end), t_end


def bounce_apexes(h0, n, kn, e, m, g):
    """Apex gaps (lowest point above the wall) after each of n bounces of a sphere dropped from gap h0."""
    v = math.sqrt(2.0 * g * h0)
    apexes = []
    for _ in range(n):
        v, _ = wall_contact(v, kn, e, m, g)
        apexes.append(v * v / (2.0 * g))
    return apexes


# ---------------------------------------------------------------------------------------------------------------
# Gas-particle drag (seed eq. 2.11-2.17). Each law is written as K = beta / (1 - eps) (N s/m^4): the force on a
# particle is V_p K (u - v) (eq. 2.18). eps is the gas volume fraction, slip = |u - v| (m/s).


def particle_reynolds(eps, d, slip, rho_g, mu):
    """Seed eq. 2.17: Re_p = eps d |u - v| rho_g / mu."""
    return eps * d * slip * rho_g / mu


def ergun_k(eps, d, slip, mu, rho_g):
    """Ergun (1952), seed eq. 2.11 with the gas viscosity restored (seed-errata 1), divided by (1 - eps):
    K = 150 (1 - eps) mu / (eps d^2) + 1.75 rho_g |u - v| / d."""
    return 150 * (1 - eps) * mu / (eps * d * d) + 1.75 * rho_g * slip / d


def cd_times_re(re):
    """Schiller-Naumann drag coefficient times Re_p, seed eq. 2.15-2.16: C_D Re = 24 (1 + 0.15 Re^0.687) for
    Re <= 1000, 0.44 Re above."""
    return 24 * (1 + 0.15 * re ** 0.687) if re <= 1000 else 0.44 * re


def wen_yu_k(eps, d, slip, mu, rho_g):
    """Wen & Yu (1966), seed eq. 2.12 divided by (1 - eps): K = 3/4 (C_D Re_p) mu eps^-2.65 / d^2."""
    return 0.75 * cd_times_re(particle_reynolds(eps, d, slip, rho_g, mu)) * mu * eps ** -2.65 / d ** 2


def ergun_wen_yu_blend(eps):
    """The smooth switch between Ergun and Wen-Yu at eps = 0.8 (Huilin et al. 2003), seed eq. 2.13 with
    seed-errata 3: phi = arctan(150 x 1.75 (eps - 0.8)) / pi + 0.5."""
    return math.atan(150 * 1.75 * (eps - 0.8)) / math.pi + 0.5


def huilin_gidaspow_k(eps, d, slip, mu, rho_g):
    """The seed's drag (-drag_model ergun_wenyu), eq. 2.14: K = (1 - phi) K_Ergun + phi K_WenYu."""
    phi = ergun_wen_yu_blend(eps)
    return (1 - phi) * ergun_k(eps, d, slip, mu, rho_g) + phi * wen_yu_k(eps, d, slip, mu, rho_g)


def terminal_velocity(k, rho_p, rho_g, g, hi=50.0):
    """The slip velocity u at which a drag law's force per particle volume, k(u) u, carries the buoyant weight per
    particle volume, (rho_p - rho_g) g: bisection on [0, hi] m/s. k is K(u) of the law as the particle feels it
    (divided by eps under Model B)."""
    lo = 0.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if k(mid) * mid < (rho_p - rho_g) * g else (lo, mid)
    return 0.5 * (lo + hi)


# ---------------------------------------------------------------------------------------------------------------
# Packed beds


def ergun_gradient(eps, u, d, mu, rho_g):
    """Ergun pressure gradient (Pa/m) through a packed bed of spheres of diameter d and voidage eps at superficial
    velocity u (seed eq. 2.11, seed-errata 1): 150 (1 - eps)^2 mu u / (eps^3 d^2) + 1.75 (1 - eps) rho_g u^2 / (eps^3 d).
    Works on arrays of u."""
    return 150 * (1 - eps) ** 2 * mu * u / (eps ** 3 * d * d) + 1.75 * (1 - eps) * rho_g * u * u / (eps ** 3 * d)


def ergun_layers(y, layer, first, last, particle_volume, area, gradient):
    """Ergun's pressure drop between the centres of layers first and last of a packed bed, applied layer by layer to
    the voidage each layer has (particle centres y counted in the layer that holds them, as the coupling does; the
    two end layers count half): the sum of weight * layer * gradient(eps of the layer). gradient(eps) is the Ergun
    gradient (ergun_gradient at the bed's velocity and gas)."""
    import numpy as np
    total = 0.0
    for j in range(first, last + 1):
        weight = 0.5 if j in (first, last) else 1.0
        n = np.sum((y >= j * layer) & (y < (j + 1) * layer))
        total += weight * layer * gradient(1 - n * particle_volume / (area * layer))
    return total


def ergun_umf(eps, d, rho_p, rho_g, mu, g):
    """Minimum fluidization velocity by Ergun: the superficial velocity at which ergun_gradient carries the bed's
    buoyant weight, (1 - eps)(rho_p - rho_g) g, for spheres of diameter d: the root of a quadratic."""
    a = 1.75 * rho_g / (eps ** 3 * d)
    b = 150 * (1 - eps) * mu / (eps ** 3 * d * d)
    c = -(rho_p - rho_g) * g
    return (-b + math.sqrt(b * b - 4 * a * c)) / (2 * a)


# ---------------------------------------------------------------------------------------------------------------
# Single-phase gas


def poiseuille_velocity(x, width, mu, f):
    """Plane Poiseuille flow between no-slip walls at x = 0 and x = width, driven by a uniform momentum source f
    (N/m^3): v(x) = f x (width - x) / (2 mu); its maximum, at the centre, is f width^2 / (8 mu)."""
    return f * x * (width - x) / (2 * mu)
