// SPDX-License-Identifier: MIT
//
// The facade's input checks (api/*.cpp): every value a script gives, and every value derived
// from it, must be finite and usable, and an error names the option and the value. Not
// installed.
#pragma once

#include <cctype>
#include <cmath>
#include <string>

#include "talus/errors.hpp"
#include "talus/vec.hpp"
#include "world/messages.hpp"

namespace talus {

inline std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Input ranges. Every value a script gives, and every value derived from it
// (mass, inertia), must be finite and usable: a radius of 1e300 gave an infinite mass, a wall at
// 1e200 m broke the broadphase (its tree stores float coordinates) and failed later blaming the
// model. Coordinates beyond 1e9 m are refused: there a double resolves 1e-7 m, coarser than the
// overlaps of a stiff contact, and the float broadphase tree (scale 0.1 / margin, margin >=
// 1e-9 m, step/detection.cpp) stays far from float overflow (3.4e38).
inline constexpr double kMaxCoordinate = 1e9;  // [m]
inline constexpr double kMinRadius = 1e-12;    // [m]

inline bool inRange(const Vec2& v) {
    return std::fabs(v.x()) <= kMaxCoordinate && std::fabs(v.y()) <= kMaxCoordinate;
}

/// Throws unless a coordinate is finite and within +-kMaxCoordinate; `what` names the option.
inline void requireCoordinate(const std::string& what, const Vec2& v) {
    if (!std::isfinite(v.x()) || !std::isfinite(v.y()))
        throw InputError(what + " must be finite (got " + vecText(v) + ")");
    if (!inRange(v))
        throw InputError(what + " " + vecText(v) + " is out of range: coordinates must be within " +
                         messageNumber(kMaxCoordinate) + " m of the origin");
}

inline void requireRadius(double r) {
    if (!(r > 0.0) || !std::isfinite(r))
        throw InputError("ball: radius must be > 0 (got " + messageNumber(r) + ")");
    if (r < kMinRadius || r > kMaxCoordinate)
        throw InputError("ball: radius " + messageNumber(r) + " m is out of range [" +
                         messageNumber(kMinRadius) + ", " + messageNumber(kMaxCoordinate) + "] m");
}

/// The kinetic energy a velocity or spin gives must be finite: vel or spin = 1e300 made the
/// energy totals infinite and balance_error -inf.
inline void requireFiniteEnergy(double mass, double inertia, const Vec2& vel, double spin) {
    if (!std::isfinite(0.5 * mass * vel.squaredNorm()))
        throw InputError("ball: vel " + vecText(vel) + " gives a ball of " + messageNumber(mass) +
                         " kg an infinite kinetic energy");
    if (!std::isfinite(0.5 * inertia * spin * spin))
        throw InputError("ball: spin " + messageNumber(spin) + " gives a ball of inertia " +
                         messageNumber(inertia) + " kg m^2 an infinite kinetic energy");
}

/// Mass and inertia of a disk or sphere; throws when either (or its inverse) is not a finite
/// positive number (a huge radius or density overflows, a tiny one underflows).
inline void requireUsableMass(double mass, double inertia, const std::string& from) {
    auto usable = [](double v) { return v > 0.0 && std::isfinite(v) && std::isfinite(1.0 / v); };
    if (!usable(mass))
        throw InputError("ball: " + from + " give a mass of " + messageNumber(mass) +
                         " kg, which is not a usable positive number");
    if (!usable(inertia))
        throw InputError("ball: " + from + " give a moment of inertia of " +
                         messageNumber(inertia) + " kg m^2, which is not a usable positive number");
}

inline void requireFinite(const char* what, const Vec2& v) {
    if (!std::isfinite(v.x()) || !std::isfinite(v.y()))
        throw InputError(std::string("ball: ") + what + " must be finite");
}

/// An inheritable contact property of a body by name: "kn", "ks" or "fric" (PFC2D 3.x).
template <class Values>  // std::vector<double>, const or not
auto& inheritableRef(Values& kn, Values& ks, Values& fric, uint32_t s, const std::string& name,
                     const char* owner) {
    const std::string n = lower(name);
    if (n == "kn") return kn[s];
    if (n == "ks") return ks[s];
    if (n == "fric") return fric[s];
    throw InputError(std::string(owner) + ": unknown contact property '" + name +
                     "' (inheritable: kn, ks, fric)");
}

}  // namespace talus
