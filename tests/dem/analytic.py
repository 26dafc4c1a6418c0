"""Analytic solutions of the linear spring-dashpot contact (seed eq. 2.3, 3.2-3.3) used by the DEM scene tests."""
import math


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
