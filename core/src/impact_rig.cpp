// SPDX-License-Identifier: MIT
//
// The single-contact rig. runImpact builds a two-body model without gravity (impactor above a
// horizontal wall or above a target ball, normal = y), runs the full engine until the contact
// has ended, and measures. Onset and end are interpolated between steps (Chung & Ooi advise it:
// step counting quantises the duration to dt). driveContact exercises a model directly.
#include "talus/impact_rig.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>

#include "props.hpp"
#include "talus/errors.hpp"

namespace talus {

namespace {

/// The bodies' state the rig reads after each step.
struct Probe {
    double overlap = 0.0;
    Vec2 v1{0.0, 0.0}, v2{0.0, 0.0};
    double w1 = 0.0, w2 = 0.0;
};

void checkSetup(const ImpactSetup& s) {
    if (!(s.radius > 0.0) || !(s.density > 0.0))
        throw InputError("impact: radius and density must be > 0");
    if (s.ball_target && (!(s.target_radius > 0.0) || !(s.target_density > 0.0)))
        throw InputError("impact: target radius and density must be > 0");
    if (!(s.normal_speed > 0.0) && !(s.target_speed > 0.0))
        throw InputError("impact: the bodies must approach (normal_speed > 0)");
}

/// The two-body model without gravity (an impactor above a horizontal wall or above a target
/// ball, normal = y) and how it is read.
struct Rig {
    Rig(const ImpactSetup& s, PluginRegistry& registry) : m_s(s), m(modelDef(s), registry) {
        m.profile().enabled = false;
        m.setDefaultContactModel(s.model, s.props);
        m.timestep() = s.timestep;
        m.guard() = s.guard;
        const double gap = s.gap >= 0.0 ? s.gap : 1e-3 * s.radius;
        double top = 0.0;  // y of the target's upper surface
        if (s.ball_target) {
            BallDef t;
            t.pos = Vec2::Zero();
            t.radius = s.target_radius;
            t.density = s.target_density;
            t.vel = Vec2(0.0, s.target_speed);
            t.spin = s.target_spin;
            m_target = m.createBall(t);
            top = s.target_radius;
        } else {
            const double half = 1e3 * s.radius;
            WallDef floor;
            floor.points = {Vec2(-half, 0.0), Vec2(half, 0.0)};
            m.createWall(floor);
        }
        BallDef imp;
        imp.pos = Vec2(0.0, top + s.radius + gap);
        imp.radius = s.radius;
        imp.density = s.density;
        imp.vel = Vec2(s.tangential_speed, -s.normal_speed);
        imp.spin = s.spin;
        m_ball = m.createBall(imp);
        m.setEnergyTracing(true);
    }

    Probe probe() const {
        Probe p;
        const Vec2 x1 = m.ballPos(m_ball);
        p.v1 = m.ballVel(m_ball);
        p.w1 = m.ballSpin(m_ball);
        if (m_s.ball_target) {
            const Vec2 x2 = m.ballPos(m_target);
            p.v2 = m.ballVel(m_target);
            p.w2 = m.ballSpin(m_target);
            p.overlap = m_s.radius + m_s.target_radius - (x1 - x2).norm();
        } else {
            p.overlap = m_s.radius - x1.y();
        }
        return p;
    }
    /// Relative normal (+ approach) and contact-point slip velocities, for the y-normal geometry.
    double normalOf(const Probe& p) const { return -(p.v1.y() - p.v2.y()); }
    double slipOf(const Probe& p) const {
        const double r2 = m_s.ball_target ? m_s.target_radius : 0.0;
        return (p.v1.x() + p.w1 * m_s.radius) - (p.v2.x() - p.w2 * r2);
    }
    ContactKey key() const {
        return ContactKey{m_s.ball_target
                              ? ((uint64_t(std::min(m_ball.index, m_target.index)) << 32) |
                                 std::max(m_ball.index, m_target.index))
                              : ((uint64_t(m_ball.index) << 32) | 0x80000000u)};
    }

    static ModelDef modelDef(const ImpactSetup& s) {
        ModelDef def;
        def.gravity = Vec2::Zero();
        def.mass_mode = s.mass_mode;
        return def;
    }

    const ImpactSetup& m_s;
    Model m;
    BallId m_ball, m_target;
};

/// The contact's times, interpolated between steps (Chung & Ooi advise it: step counting
/// quantises the duration to dt): onset, end of overlap, end of force.
struct Times {
    double on = 0.0, off = 0.0, force_off = 0.0;
};

/// Steps until the contact has ended (or max_steps): the steps in contact, the largest overlap
/// and force, the trace, the times. Returns true when the bodies separated.
bool runContact(Rig& rig, const ImpactSetup& s, ImpactResult& r, Times& times) {
    Model& m = rig.m;
    const ContactKey key = rig.key();
    Probe prev = rig.probe();
    double t_prev = m.time();
    double f_prev = 0.0;
    bool touched = false, force_on = false;
    for (int64_t step = 0; step < s.max_steps; ++step) {
        m.cycle(1);
        const Probe now = rig.probe();
        const double t = m.time();
        ContactInfo c;
        const bool active = m.findContact(key, c) && c.active;
        const double fn = active ? c.normal_force : 0.0;
        if (!touched && now.overlap > 0.0) {
            touched = true;
            const double f = -prev.overlap / (now.overlap - prev.overlap);
            times.on = t_prev + f * (t - t_prev);
            r.timestep = m.lastTimestep();
            r.step_rule = m.lastStepReason();
        }
        if (touched) {
            if (now.overlap > 0.0) ++r.steps_in_contact;
            r.max_overlap = std::max(r.max_overlap, now.overlap);
            r.peak_force = std::max(r.peak_force, fn);
            if (s.keep_trace)
                r.trace.push_back(TracePoint{t, now.overlap, fn, active ? c.shear_force : 0.0,
                                             active ? c.moment : 0.0});
            if (fn > 0.0) force_on = true;
            if (force_on && f_prev > 0.0 && fn <= 0.0)
                times.force_off = t_prev + (t - t_prev) * f_prev / (f_prev - fn);
            if (prev.overlap > 0.0 && now.overlap <= 0.0)
                times.off = t_prev + (t - t_prev) * prev.overlap / (prev.overlap - now.overlap);
            if (now.overlap <= 0.0 && !active && rig.normalOf(now) < 0.0) return true;
        }
        prev = now;
        t_prev = t;
        f_prev = fn;
    }
    return false;
}

/// The outcome after the contact: velocities, restitutions, angles, durations, energies.
void readOutcome(const Rig& rig, Times times, ImpactResult& r) {
    const Probe end = rig.probe();
    r.vn_out = rig.normalOf(end);
    r.vt_out = end.v1.x() - end.v2.x();
    r.slip_out = rig.slipOf(end);
    r.spin_out = end.w1;
    r.target_spin_out = end.w2;
    r.restitution = r.vn_in != 0.0 ? -r.vn_out / r.vn_in : 0.0;
    r.tangential_restitution = r.vt_in != 0.0 ? r.vt_out / r.vt_in : 0.0;
    r.rebound_angle = std::atan2(std::fabs(end.v1.x()), std::fabs(end.v1.y()));
    r.contact_point_angle = r.vn_out != 0.0 ? std::atan(r.slip_out / -r.vn_out) : 0.0;
    if (times.force_off <= times.on) times.force_off = times.off;
    r.duration = (times.off > times.on ? times.off : times.force_off) - times.on;
    r.force_duration = times.force_off - times.on;
    r.energy = rig.m.energies();
    r.energy_out = r.energy.kinetic;
}

}  // namespace

ImpactResult runImpact(const ImpactSetup& s, PluginRegistry& registry) {
    checkSetup(s);
    Rig rig(s, registry);
    ImpactResult r;
    const Probe p0 = rig.probe();
    r.vn_in = rig.normalOf(p0);
    r.vt_in = p0.v1.x() - p0.v2.x();
    r.slip_in = rig.slipOf(p0);
    r.energy_in = rig.m.energies().initial_kinetic;
    Times times;
    r.separated = runContact(rig, s, r, times);
    // One step applies what the model owed at separation (closing impulses), one more brings the
    // energy snapshot (one step behind, docs/physics/energy.md) past the contact.
    if (r.separated) rig.m.cycle(2);
    readOutcome(rig, times, r);
    return r;
}

DriveResult driveContact(const DriveSetup& s, PluginRegistry& registry) {
    if (!(s.dt > 0.0)) throw InputError("drive: dt must be > 0");
    if (!s.shear.empty() && s.shear.size() != s.overlap.size())
        throw InputError("drive: shear must have as many samples as overlap");
    const ModelFactory& f = registry.find(s.model);
    auto proto = registry.createPrototype(f);
    applyProps(*proto, s.props, "drive");
    PropBlock pb = emptyPropBlock();
    pb.end2_type = s.ball_target ? kEndBall : kEndWall;
    pb.radius[0] = s.radius;
    pb.radius[1] = s.ball_target ? s.target_radius : 0.0;
    pb.mass[0] = s.mass;
    pb.mass[1] = s.ball_target ? s.target_mass : 0.0;
    pb.mass_eff = s.ball_target ? s.mass * s.target_mass / (s.mass + s.target_mass) : s.mass;
    if (const char* err = proto->PreCycle(pb)) throw InputError(std::string("drive: ") + err);

    const std::size_t words =
        (proto->ObjectSize() + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t);
    std::vector<std::max_align_t> storage(words);
    auto clone = [&]() {
        ContactModel* c = proto->Clone(pb, storage.data());
        if (!c) throw PluginError("drive: cannot create '" + f.name + "': " + proto->LastError());
        return c;
    };
    ContactModel* model = clone();
    struct DestroyAtExit {  // also when FDlaw fails and we throw
        ContactModel*& m;
        ~DestroyAtExit() {
            if (m) m->Destroy();
        }
    } destroy_at_exit{model};
    const double activity = proto->ActivityDistance();

    DriveResult out;
    FdBlock fd{};
    fd.size = sizeof(FdBlock);
    fd.version = TALUS_ABI_MAJOR * 1000 + TALUS_ABI_MINOR;
    fd.tdel = s.dt;
    fd.mass_eff = pb.mass_eff;
    // Disks touching at their rims: r^2 / I = 2 / m per end.
    fd.inv_mass_eff_s = 3.0 / s.mass + (s.ball_target ? 3.0 / s.target_mass : 0.0);
    bool active = false;
    double u_prev = 0.0, us_prev = 0.0;
    for (std::size_t i = 0; i < s.overlap.size(); ++i) {
        const double u = s.overlap[i];
        const double us = s.shear.empty() ? 0.0 : s.shear[i];
        fd.du_n = u - u_prev;
        fd.du_s = us - us_prev;
        fd.u_dot_n = fd.du_n / s.dt;
        fd.u_dot_s = fd.du_s / s.dt;
        u_prev = u;
        us_prev = us;
        fd.time = static_cast<double>(i) * s.dt;
        if (!active && u <= -activity) {
            out.trace.push_back(TracePoint{fd.time, u, 0.0, 0.0, 0.0});
            out.knest.push_back(model->KnEstimate());
            continue;
        }
        fd.flags = kFdEnergyOn | (active ? 0u : kFdFirstCall);
        active = true;
        fd.u_n = u;
        fd.status = 0;
        for (double& e : fd.energy) e = 0.0;
        model->FDlaw(fd);
        if (fd.status != 0)
            throw PluginError("drive: model '" + f.name + "' failed at sample " +
                              std::to_string(i) + ": " + (fd.error ? fd.error : "(no message)"));
        out.trace.push_back(TracePoint{fd.time, u, fd.n_force, fd.s_force, fd.moment});
        out.knest.push_back(fd.knest);
        out.strain = fd.energy[kEnergyStrain];
        out.slip += fd.energy[kEnergySlip];
        out.dashpot += fd.energy[kEnergyDashpot];
        out.plastic += fd.energy[kEnergyPlastic];
        if (u <= -activity && !(fd.flags & kFdKeep) && model->OKToDelete()) {
            model->Destroy();
            model = nullptr;
            model = clone();
            active = false;
            fd.n_force = fd.s_force = fd.moment = 0.0;
        }
    }
    return out;
}

void writeTraceCsv(const std::vector<TracePoint>& trace, const std::string& path) {
    std::ofstream os(path);
    if (!os) throw InputError("cannot write trace file '" + path + "'");
    os.precision(12);
    os << "time,overlap,normal_force,shear_force,moment\n";
    for (const auto& p : trace)
        os << p.time << ',' << p.overlap << ',' << p.normal_force << ',' << p.shear_force << ','
           << p.moment << '\n';
}

}  // namespace talus
