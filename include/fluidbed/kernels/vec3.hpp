// Small fixed-size vector used by the DEM and drag kernels.
//
// Kernels are header-only free functions over scalars and small structs (no PETSc, no MPI) so that unit tests
// call them directly. Every operation is written so that swapping the two bodies of a contact negates the
// result bit for bit (a - b == -(b - a) in IEEE arithmetic); the contact loop relies on this for
// decomposition-independent forces.
#pragma once

#include <cmath>

namespace fluidbed::kernels {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
};

inline Vec3 operator+(const Vec3 &a, const Vec3 &b)
{
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(const Vec3 &a, const Vec3 &b)
{
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator-(const Vec3 &a)
{
  return {-a.x, -a.y, -a.z};
}
inline Vec3 operator*(double s, const Vec3 &a)
{
  return {s * a.x, s * a.y, s * a.z};
}
inline Vec3 operator*(const Vec3 &a, double s)
{
  return {s * a.x, s * a.y, s * a.z};
}
inline Vec3 &operator+=(Vec3 &a, const Vec3 &b)
{
  a.x += b.x;
  a.y += b.y;
  a.z += b.z;
  return a;
}
inline Vec3 &operator-=(Vec3 &a, const Vec3 &b)
{
  a.x -= b.x;
  a.y -= b.y;
  a.z -= b.z;
  return a;
}
inline double dot(const Vec3 &a, const Vec3 &b)
{
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(const Vec3 &a, const Vec3 &b)
{
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm2(const Vec3 &a)
{
  return dot(a, a);
}
inline double norm(const Vec3 &a)
{
  return std::sqrt(dot(a, a));
}

} // namespace fluidbed::kernels
