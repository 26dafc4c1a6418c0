// Linear spring-dashpot soft-sphere contact with tangential overlap history and a Coulomb slider.
//
// Seed (dissertation on DEM-CFD of jetting beds) chapter 2, eq. 2.3-2.10, after Cundall & Strack (1979) and
// Tsuji, Kawaguchi & Tanaka (1993); damping and critical time from eq. 3.2-3.3 (see seed-errata 5).
//
// Convention (seed-errata 2): n points from the centre of body i towards body j (or towards the wall), the
// overlap delta is positive in contact, and v_rel is the velocity of i's surface relative to j's surface at
// the contact point,
//     v_rel = v_i - v_j + (r_i w_i + r_j w_j) x n .
// The normal force on i is f_n = -k_n delta n - eta_n (v_rel . n) n (it pushes i away from j), the tangential
// force f_t = -k_t xi_t - eta_t v_t with xi_t the accumulated tangential displacement, limited by
// |f_t| <= mu |f_n| (eq. 2.8). The torque on i is r_i n x f_t (eq. 2.10). Walls are bodies of infinite radius
// and mass at rest: m_eff = m_i and no rotation term for the wall.
//
// Swapping i and j negates n, v_rel and the history, and the kernel returns exactly the negated force: the
// arithmetic below is arranged so that this holds bit for bit.
#pragma once

#include <cmath>

#include "fluidbed/kernels/vec3.hpp"

namespace fluidbed::kernels {

// Damping ratio from the coefficient of restitution, eq. 3.3: gamma = -ln e / sqrt(pi^2 + ln^2 e); 0 for e = 1.
inline double restitution_damping_ratio(double e)
{
  const double le = std::log(e);
  return -le / std::sqrt(M_PI * M_PI + le * le);
}

// Contact duration of the linear spring-dashpot, eq. 3.2: t_cr = pi / sqrt(k_n (1 - gamma^2) / m_eff).
// With m_eff = m/2 (equal particles), k_n = 800 N/m and e = 0.9 this gives 3.675e-5 s for 550 um glass
// and 5.838e-5 s for 750 um glass, the seed's values.
inline double critical_time(double kn, double e, double m_eff)
{
  const double g = restitution_damping_ratio(e);
  return M_PI / std::sqrt(kn * (1.0 - g * g) / m_eff);
}

// Damping coefficient eta = 2 gamma sqrt(m_eff k) (N s/m) that yields restitution e for a linear spring k.
inline double damping_coefficient(double k, double e, double m_eff)
{
  return 2.0 * restitution_damping_ratio(e) * std::sqrt(m_eff * k);
}

// Parameters of one contact type (particle-particle or particle-wall). The damping coefficients depend on the
// pair's effective mass, eta = damp * sqrt(m_eff), so one model serves polydisperse beds.
struct LsdModel {
  double kn     = 0.0; // normal spring stiffness, N/m
  double kt     = 0.0; // tangential spring stiffness, N/m
  double damp_n = 0.0; // 2 gamma sqrt(kn), sqrt(N/m)
  double damp_t = 0.0; // 2 gamma sqrt(kt): same damping ratio in both directions
  double mu     = 0.0; // Coulomb friction coefficient
};

inline LsdModel lsd_model(double kn, double kt, double e, double mu)
{
  const double g = restitution_damping_ratio(e);
  return {kn, kt, 2.0 * g * std::sqrt(kn), 2.0 * g * std::sqrt(kt), mu};
}

// Geometry and relative motion of one contact, as seen from body i.
struct ContactKinematics {
  Vec3   n;               // unit normal from i towards j
  double overlap = 0.0;   // delta_n, > 0 in contact
  Vec3   v_rel;           // contact-point velocity of i relative to j
  double sqrt_meff = 0.0; // square root of the effective mass, sqrt(kg)
};

// sqrt(m_i m_j / (m_i + m_j)): constant for a pair, so callers compute it once per neighbour-list entry.
// Symmetric in i and j bit for bit.
inline double sqrt_effective_mass(double mi, double mj)
{
  return std::sqrt(mi * mj / (mi + mj));
}

// Kinematics of a particle pair from what the pair's bodies give it: dij = x_j - x_i (minimum image in periodic
// directions), dist = |dij| > 0, rsum = r_i + r_j, v_diff = v_i - v_j and w_sum = r_i w_i + r_j w_j. The contact loop
// gathers these for many pairs and evaluates them in SIMD lanes (src/contact/contact_lsd.cpp).
inline ContactKinematics pair_kinematics_from(const Vec3 &dij, double dist, double rsum, const Vec3 &v_diff, const Vec3 &w_sum,
                                              double sqrt_meff)
{
  ContactKinematics k;
  const double      inv = 1.0 / dist;
  k.n                   = inv * dij;
  k.overlap             = rsum - dist;
  k.v_rel               = v_diff + cross(w_sum, k.n);
  k.sqrt_meff           = sqrt_meff;
  return k;
}

// Kinematics of a particle pair. dij = x_j - x_i (minimum image in periodic directions), dist = |dij| > 0.
inline ContactKinematics pair_kinematics(const Vec3 &dij, double dist, double ri, double rj, const Vec3 &vi, const Vec3 &vj, const Vec3 &wi,
                                         const Vec3 &wj, double sqrt_meff)
{
  return pair_kinematics_from(dij, dist, ri + rj, vi - vj, ri * wi + rj * wj, sqrt_meff);
}

// Kinematics of a particle against a plane wall at rest. n_wall is the unit normal pointing from the particle
// into the wall, gap the distance from the particle centre to the wall plane; m_eff = m_i.
inline ContactKinematics wall_kinematics(const Vec3 &n_wall, double gap, double ri, const Vec3 &vi, const Vec3 &wi, double mi)
{
  ContactKinematics k;
  k.n         = n_wall;
  k.overlap   = ri - gap;
  k.v_rel     = vi + cross(ri * wi, n_wall);
  k.sqrt_meff = std::sqrt(mi);
  return k;
}

struct ContactForce {
  Vec3   normal;          // f_n on i, N
  Vec3   tangential;      // f_t on i, N (torque on i is r_i n x f_t)
  double damping_n = 0.0; // the dashpot part of f_n along n, -eta_n (v_rel . n), N
  double eta_n     = 0.0; // the pair's normal damping coefficient damp_n sqrt(m_eff), N s/m
};

// Bring the stored tangential displacement into the current tangent plane, so that a rolling pair does not
// turn history into a normal component. As in LAMMPS's hooke/history, the normal part is removed without
// rescaling: the normal turns by ~1e-4 rad per step, so the length lost is ~1e-8 of xi per step, and the
// rescaling's division and root cost 15% of the contact loop.
inline Vec3 project_history(const Vec3 &xi, const Vec3 &n)
{
  return xi - dot(xi, n) * n;
}

// Eq. 2.3-2.8 for one contact over one time step dt. xi_t is the tangential displacement (history) of this
// contact: zero when the contact forms, updated in place, and stored by the caller between steps.
inline ContactForce lsd_contact(const LsdModel &m, const ContactKinematics &k, double dt, Vec3 &xi_t)
{
  const double sqrt_meff = k.sqrt_meff;
  const double vn_mag    = dot(k.v_rel, k.n);
  const Vec3   vn        = vn_mag * k.n;
  const Vec3   vt        = k.v_rel - vn;

  ContactForce f;
  f.eta_n     = m.damp_n * sqrt_meff;
  f.damping_n = -f.eta_n * vn_mag;
  f.normal    = -(m.kn * k.overlap) * k.n + f.damping_n * k.n; // eq. 2.3

  xi_t               = project_history(xi_t, k.n) + dt * vt;
  const double eta_t = m.damp_t * sqrt_meff;
  f.tangential       = -m.kt * xi_t - eta_t * vt; // eq. 2.4
  const double ft2   = norm2(f.tangential);
  const double fmax2 = m.mu * m.mu * norm2(f.normal); // eq. 2.8, Coulomb slider
  // Selects, not a branch, so that the contact loop can evaluate contacts in SIMD lanes: the root and the
  // division are taken in every contact (on a divisor that cannot be zero) and used only by one that slides; the
  // others keep their force and history bit for bit (1 * x is x).
  const bool   slides = ft2 > fmax2;
  const double root   = std::sqrt(fmax2 / (slides ? ft2 : 1.0));
  const double scale  = slides ? root : 1.0;
  f.tangential        = scale * f.tangential;
  // The spring stretches no further than the slider allows: keep xi consistent with the limited force.
  const bool   spring   = m.kt > 0.0;
  const double neg_c    = -1.0 / (spring ? m.kt : 1.0);
  const Vec3   xi_slide = neg_c * (f.tangential + eta_t * vt);
  xi_t.x                = slides ? (spring ? xi_slide.x : 0.0) : xi_t.x;
  xi_t.y                = slides ? (spring ? xi_slide.y : 0.0) : xi_t.y;
  xi_t.z                = slides ? (spring ? xi_slide.z : 0.0) : xi_t.z;
  return f;
}

// Exact dashpot impulse over a time step. The normal dashpot force -eta_n v_n acts only while the bodies overlap,
// and v_n is the rate of change of the overlap, so its impulse over a step is exactly -eta_n times the change of
// the (positive part of the) overlap, whenever the contact began or ended. Velocity Verlet's trapezoid gives
// dt/2 (f_d,prev + f_d) instead, which is first order in dt when the force jumps on or off inside the step. This
// returns the difference, added to body i's closing half kick: with it the restitution of eq. 3.3 is second
// order in dt (docs/dem.md). overlap_* are max(delta, 0); damping_* the scalar dashpot forces along n (0 out of
// contact); n is the current normal and eta_n = damp_n sqrt(m_eff).
inline Vec3 damping_impulse_correction(double eta_n, double overlap_prev, double overlap_now, double damping_prev, double damping_now,
                                       double half_dt, const Vec3 &n)
{
  return (-eta_n * (overlap_now - overlap_prev) - half_dt * (damping_prev + damping_now)) * n;
}

// Elastic energy held by one contact's springs, 1/2 k_n delta^2 + 1/2 k_t |xi_t|^2 (J): with the kinetic and the
// gravitational energy it is what the contacts conserve at e = 1 and mu = 0 and only lose otherwise (the energy
// guard, kernels/guard_rules.hpp).
inline double lsd_elastic_energy(const LsdModel &m, double overlap, const Vec3 &xi_t)
{
  return 0.5 * m.kn * overlap * overlap + 0.5 * m.kt * norm2(xi_t);
}

} // namespace fluidbed::kernels
