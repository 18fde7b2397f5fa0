// SPDX-License-Identifier: MIT
//
// Helpers for the tests of the hertz, ng, hysdamp and linear contact models: a fixed-seed PRNG
// for the phase of first touch, error statistics, closed forms of single impacts (each cites its
// source), the Chung & Ooi materials
// (Chung & Ooi 2011), a per-contact model object driven directly through the ABI (for
// SaveRestore tests), and an RK4 reference integrator for single normal impacts whose closed
// form is not known (damped Hertz).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "talus/contact_model.hpp"
#include "talus/errors.hpp"
#include "talus/impact_rig.hpp"
#include "talus/model.hpp"
#include "talus/plugin_registry.hpp"
#include "talus/save_object.hpp"
#include "talus/splitmix.hpp"

namespace talus::lawtest {

/// The fixed-seed generator of the scenes (talus/splitmix.hpp).
using Rng = SplitMix64;

struct Stats {
    double worst = 0.0, sum = 0.0;
    int n = 0;
    void add(double v) {
        worst = std::max(worst, std::fabs(v));
        sum += std::fabs(v);
        ++n;
    }
    double mean() const { return n ? sum / n : 0.0; }
};

inline double diskMass(double rho, double r) { return rho * M_PI * r * r; }
inline double sphereMass(double rho, double r) { return rho * 4.0 / 3.0 * M_PI * r * r * r; }

// ------------------------------------------------------------------ Hertz (accuracy-ref 1.2)

struct HertzImpact {
    double dmax, fmax, tc;
};

/// Elastic Hertz impact: maximum overlap, peak force and duration for m*, R*, E*, v0.
/// 2.9432 = 2 sqrt(pi) Gamma(7/5) / Gamma(9/10), computed to full precision.
inline HertzImpact hertzImpact(double m_eff, double r_eff, double e_eff, double v0) {
    HertzImpact h;
    h.dmax = std::pow(15.0 * m_eff * v0 * v0 / (16.0 * e_eff * std::sqrt(r_eff)), 0.4);
    h.fmax = 4.0 / 3.0 * e_eff * std::sqrt(r_eff) * std::pow(h.dmax, 1.5);
    const double factor = 2.0 * std::sqrt(M_PI) * std::tgamma(1.4) / std::tgamma(0.9);
    h.tc = factor * h.dmax / v0;
    return h;
}

/// A material of Chung & Ooi 2011 (E [Pa], nu, rho [kg/m^3]) and its shear modulus.
struct Material {
    const char* name;
    double E, nu, rho;
    double G() const { return E / (2.0 * (1.0 + nu)); }
};

// ------------------------------------------------------------------ bilinear (accuracy-ref 1.3)

/// Free-impact restitution of hysdamp: sqrt(d) without tension (Walton & Braun 1986); with
/// the tension branch (slope k_load below the residual overlap) the bodies also lose
/// (1/2) k_load u0^2 = (1-d)^2 of the impact energy: e^2 = d - (1-d)^2.
inline double hysdampRestitution(double d, bool tension) {
    return tension ? std::sqrt(d - (1.0 - d) * (1.0 - d)) : std::sqrt(d);
}

// ------------------------------------------------------------------ reference integrator

/// Integrates m x'' = -f(x, x') from x = 0, x' = v0 (x the overlap) with classical RK4 at
/// `steps_per_unit` steps per time unit t_unit, until `ended(x, x')` holds after the overlap
/// peaked; returns -x'/v0 at the end (linear interpolation of the end event in x).
inline double referenceRestitution(double m, double v0, double t_unit,
                                   const std::function<double(double, double)>& force,
                                   const std::function<double(double, double)>& end_value,
                                   int steps_per_unit = 200000) {
    const double h = t_unit / steps_per_unit;
    double x = 0.0, v = v0;
    auto acc = [&](double xx, double vv) { return -force(xx, vv) / m; };
    double g_prev = end_value(x, v);
    for (int i = 0; i < 20 * steps_per_unit; ++i) {
        const double k1x = v, k1v = acc(x, v);
        const double k2x = v + 0.5 * h * k1v, k2v = acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
        const double k3x = v + 0.5 * h * k2v, k3v = acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
        const double k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v);
        const double xn = x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
        const double vn = v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
        const double g = end_value(xn, vn);
        if (vn < 0.0 && g <= 0.0 && g_prev > 0.0) {
            const double f = g_prev / (g_prev - g);
            return -(v + f * (vn - v)) / v0;
        }
        x = xn, v = vn, g_prev = g;
    }
    return NAN;
}

// ------------------------------------------------------------------ a contact without a model

/// One per-contact model object, cloned from a prototype the way the engine does, and stepped
/// with FdBlocks filled by hand: for SaveRestore and property tests below the engine.
class LawDriver {
public:
    LawDriver(const std::string& model, const std::vector<PropValue>& props, bool ball_target,
              double radius, double target_radius, double mass_eff)
        : m_factory(PluginRegistry::global().find(model)),
          m_proto(PluginRegistry::global().createPrototype(m_factory)) {
        for (const auto& p : props) {
            int32_t idx = -1;
            for (int32_t i = 0; i < m_proto->PropCount(); ++i)
                if (std::string(m_proto->PropInfoAt(i)->name) == p.name) idx = i;
            if (idx < 0) throw InputError("LawDriver: no property " + p.name);
            if (m_proto->AcceptProp(idx, p.value) != 0) throw InputError(m_proto->LastError());
        }
        m_pb.size = sizeof(PropBlock);
        m_pb.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
        m_pb.end2_type = ball_target ? kEndBall : kEndWall;
        for (int i = 0; i < 2; ++i) m_pb.kn[i] = m_pb.ks[i] = m_pb.fric[i] = NAN;
        m_pb.radius[0] = radius;
        m_pb.radius[1] = ball_target ? target_radius : 0.0;
        m_pb.mass_eff = mass_eff;
        if (const char* err = m_proto->PreCycle(m_pb)) throw InputError(err);
    }
    ~LawDriver() {
        for (auto* c : m_objects) c->Destroy();
    }
    LawDriver(const LawDriver&) = delete;
    LawDriver& operator=(const LawDriver&) = delete;

    /// A fresh per-contact object (owned by the driver).
    ContactModel* clone() {
        m_storage.emplace_back((m_proto->ObjectSize() + sizeof(std::max_align_t) - 1) /
                               sizeof(std::max_align_t));
        ContactModel* c = m_proto->Clone(m_pb, m_storage.back().data());
        if (!c) throw PluginError(m_proto->LastError());
        m_objects.push_back(c);
        return c;
    }
    const ContactModel& prototype() const { return *m_proto; }
    const PropBlock& propBlock() const { return m_pb; }

    /// An FdBlock for overlap u, rates and step dt; forces carried over from `prev`.
    FdBlock block(double u, double u_dot_n, double u_dot_s, double dt, const FdBlock* prev) const {
        FdBlock fd{};
        fd.size = sizeof(FdBlock);
        fd.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
        fd.flags = kFdEnergyOn | (prev ? 0u : kFdFirstCall);
        fd.u_n = u;
        fd.u_dot_n = u_dot_n;
        fd.u_dot_s = u_dot_s;
        fd.tdel = dt;
        fd.du_n = u_dot_n * dt;
        fd.du_s = u_dot_s * dt;
        fd.mass_eff = m_pb.mass_eff;
        if (prev) fd.n_force = prev->n_force, fd.s_force = prev->s_force, fd.moment = prev->moment;
        return fd;
    }

private:
    const ModelFactory& m_factory;
    PluginRegistry::PrototypePtr m_proto;
    PropBlock m_pb{};
    std::vector<std::vector<std::max_align_t>> m_storage;
    std::vector<ContactModel*> m_objects;
};

/// Drives two objects through the same history: `a` to the middle, saved, restored into a fresh
/// `b`, then both to the end. Returns true if every output of the second half is bit-identical.
/// `u` and `us` give overlap and shear displacement per sample.
inline bool saveRestoreContinuesExactly(LawDriver& drv, const std::vector<double>& u,
                                        const std::vector<double>& us, double dt, std::size_t split,
                                        int* compared = nullptr) {
    ContactModel* a = drv.clone();
    FdBlock fa{};
    bool have = false;
    auto step = [&](ContactModel* m, FdBlock& fd, bool& has, std::size_t i) {
        const double un = i ? u[i - 1] : 0.0, usp = i ? us[i - 1] : 0.0;
        FdBlock next =
            drv.block(u[i], (u[i] - un) / dt, (us[i] - usp) / dt, dt, has ? &fd : nullptr);
        m->FDlaw(next);
        fd = next;
        has = true;
    };
    for (std::size_t i = 0; i < split; ++i) step(a, fa, have, i);
    BinarySaveObject saver(a->Version());
    a->SaveRestore(saver);
    ContactModel* b = drv.clone();
    BinarySaveObject loader(saver.bytes(), a->Version());
    b->SaveRestore(loader);
    if (!loader.atEnd()) return false;
    FdBlock fb = fa;
    bool hb = true;
    int n = 0;
    for (std::size_t i = split; i < u.size(); ++i) {
        step(a, fa, have, i);
        step(b, fb, hb, i);
        const bool same = fa.n_force == fb.n_force && fa.s_force == fb.s_force &&
                          fa.moment == fb.moment && fa.knest == fb.knest && fa.ksest == fb.ksest;
        for (int k = 0; k < kEnergyCount; ++k)
            if (fa.energy[k] != fb.energy[k]) return false;
        if (!same) return false;
        ++n;
    }
    for (int32_t i = 0; i < a->PropCount(); ++i) {
        const double x = a->ReturnProp(i), y = b->ReturnProp(i);
        if (!(x == y || (std::isnan(x) && std::isnan(y)))) return false;
    }
    if (compared) *compared = n;
    return true;
}

/// The message of the InputError that setting the default contact model throws, or "" if none.
inline std::string modelError(const std::string& model, const std::vector<PropValue>& props) {
    try {
        Model m;
        m.setDefaultContactModel(model, props);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace talus::lawtest
