#pragma once
// W lanes of T as one value (GCC's vector extension), with the arithmetic a collision uses, so
// that a collision written for a scalar T runs unchanged on W cells at once. Every operation is
// the scalar one lane by lane (no fused multiply-add: the project compiles with
// -ffp-contract=off), so the results are those of the scalar code bit for bit.
#include <cstring>
#include <utility>

namespace lbsolid::fluid {

template <class T, int W>
struct Lanes {
  typedef T Vector __attribute__((vector_size(W * sizeof(T))));
  Vector v;

  Lanes() = default;
  constexpr Lanes(Vector x) : v(x) {}
  // A scalar in every lane, rounded to T once as the scalar code's T(x) is.
  constexpr Lanes(double x) : v(Vector{} + static_cast<T>(x)) {}

  static Lanes load(const T* p) {  // any alignment
    Lanes r;
    std::memcpy(&r.v, p, sizeof(Vector));
    return r;
  }
  // p on a multiple of the vector's size (through memcpy: T's arrays are not accessed as Vector).
  static Lanes load_aligned(const T* p) {
    Lanes r;
    std::memcpy(&r.v, __builtin_assume_aligned(p, sizeof(Vector)), sizeof(Vector));
    return r;
  }
  // W values `stride` apart, lane l from p[l stride].
  static Lanes load_strided(const T* p, long stride) {
    return [&]<int... I>(std::integer_sequence<int, I...>) { return Lanes(Vector{p[I * stride]...}); }(
        std::make_integer_sequence<int, W>{});
  }
  void store(T* p) const { std::memcpy(p, &v, sizeof(Vector)); }  // any alignment
  void store_aligned(T* p) const { std::memcpy(__builtin_assume_aligned(p, sizeof(Vector)), &v, sizeof(Vector)); }

  friend constexpr Lanes operator+(Lanes a, Lanes b) { return Lanes(a.v + b.v); }
  friend constexpr Lanes operator-(Lanes a, Lanes b) { return Lanes(a.v - b.v); }
  friend constexpr Lanes operator*(Lanes a, Lanes b) { return Lanes(a.v * b.v); }
  friend constexpr Lanes operator/(Lanes a, Lanes b) { return Lanes(a.v / b.v); }
  friend constexpr Lanes operator-(Lanes a) { return Lanes(-a.v); }
  Lanes& operator+=(Lanes b) { return *this = *this + b; }
  Lanes& operator-=(Lanes b) { return *this = *this - b; }
  Lanes& operator*=(Lanes b) { return *this = *this * b; }
};

// Lanes taken from the 2W lanes of a then b, starting at lane `first`: first = 1 gives a's lanes
// 1..W-1 and b's lane 0 (the next cell's values, one further on).
template <int First, class T, int W>
inline Lanes<T, W> lanes_from(Lanes<T, W> a, Lanes<T, W> b) {
  return [&]<int... I>(std::integer_sequence<int, I...>) {
    return Lanes<T, W>(__builtin_shufflevector(a.v, b.v, (First + I)...));
  }(std::make_integer_sequence<int, W>{});
}

}  // namespace lbsolid::fluid
