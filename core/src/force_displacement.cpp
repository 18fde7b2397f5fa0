// SPDX-License-Identifier: MIT
//
// Phase 4: the force-displacement law. One pass over the pairs does, for each:
//   narrowphase geometry -> (touching?) -> FdBlock -> the contact's model FDlaw -> forces and
//   moments onto both ends; and, only when the scene asks for them, the stiffness sums and pair
//   limits for the next automatic step, energy partitions, and the stability guard's work count.
// Those three extras are template switches, so a fixed-step run without tracing pays nothing
// for them (docs/architecture.md, "Pay only for what a scene uses").
//
// Frame: n from end 1 to end 2, t = perp(n); the model's forces act on end 2, end 1 gets the
// opposite; torques are (contact point - centre) x force, plus the model's moment.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "model_internal.hpp"
#include "narrowphase.hpp"
#include "talus/errors.hpp"
#include "talus/sdk/dashpot.hpp"

namespace talus {

namespace {

constexpr std::size_t kPrefetchAhead = 4;
/// Steps in contact the guard follows a contact for (docs/physics/guard.md).
constexpr uint32_t kGuardWatch = 400;

std::string num(double v) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

}  // namespace

void Model::forceDisplacement() {
    const bool automatic = m_timestep.automatic;
    const bool guard = m_guard.energy != GuardAction::Off ||
                       m_guard.resolution != GuardAction::Off ||
                       m_guard.stiffness != GuardAction::Off;
    // Dispatch once per step to the loop compiled for exactly what this scene needs.
    if (automatic) {
        if (m_energy_on)
            guard ? forceLoop<true, true, true>() : forceLoop<true, true, false>();
        else
            guard ? forceLoop<true, false, true>() : forceLoop<true, false, false>();
    } else {
        if (m_energy_on)
            guard ? forceLoop<false, true, true>() : forceLoop<false, true, false>();
        else
            guard ? forceLoop<false, false, true>() : forceLoop<false, false, false>();
    }
}

template <bool kAuto, bool kEnergy, bool kGuard>
void Model::forceLoop() {
    auto& b = *m_balls;
    std::fill(b.force.begin(), b.force.end(), Vec2::Zero());
    std::fill(b.moment.begin(), b.moment.end(), 0.0);
    for (auto& w : m_walls) w.force.setZero(), w.moment = 0.0;
    if constexpr (kAuto) {
        std::fill(b.k_tran.begin(), b.k_tran.end(), 0.0);
        std::fill(b.k_rot.begin(), b.k_rot.end(), 0.0);
        m_limits = StepLimits{};
        m_limits_stale = false;
    }
    const double dt = m_dt;
    FdBlock fd = m_fd_template;
    fd.tdel = dt;
    fd.time = m_time;
    double strain_now = 0.0, bond_now = 0.0;
    double finite_check = 0.0;
    m_to_remove.clear();
    const Vec2* pos = b.pos.data();
    const Vec2* vel = b.vel.data();
    const double* radius = b.radius.data();
    const double* spin = b.spin.data();
    Vec2* force = b.force.data();
    double* moment = b.moment.data();

    const std::size_t npairs = m_pairs.size();
    for (std::size_t i = 0; i < npairs; ++i) {
        Pair& p = m_pairs[i];
        // The contact objects live apart from the pairs, which only point to them: ask for the
        // first three cache lines of the object a few pairs ahead (the shipped models' objects
        // are 88 to 184 bytes).
        if (i + kPrefetchAhead < npairs) {
            const Pair& ahead = m_pairs[i + kPrefetchAhead];
            if (ahead.active) {
                const char* obj = reinterpret_cast<const char*>(ahead.model);
                __builtin_prefetch(obj);
                __builtin_prefetch(obj + 64);
                __builtin_prefetch(obj + 128);
            }
        }
        const uint32_t s1 = p.end1;
        const Vec2 x1 = pos[s1];
        const double r1 = radius[s1];
        ContactGeometry g;
        Vec2 v2c, x2;
        double spin2;

        if (!p.wall) {
            const uint32_t s2 = p.end2;
            x2 = pos[s2];
            const Vec2 d = x2 - x1;
            const double rsum = r1 + radius[s2];
            const double dist2 = d.squaredNorm();
            const double reach = rsum + p.activity;
            if (!p.active && dist2 >= reach * reach) {
                if constexpr (kAuto) {
                    const double dist = std::sqrt(dist2);
                    const Vec2 arel = (force[s2] + b.fapp[s2]) * b.inv_mass[s2] -
                                      (force[s1] + b.fapp[s1]) * b.inv_mass[s1];
                    noteApproach(p, m_cold[i], dist - rsum, vel[s2] - vel[s1], arel.norm(),
                                 dist > 0.0 ? Vec2(d / dist) : Vec2(0.0, 1.0));
                }
                if ((m_ball_moved[s1] | m_ball_moved[s2]) && !b.fat[s1].overlaps(b.fat[s2]))
                    m_to_remove.push_back(static_cast<uint32_t>(i));
                continue;
            }
            const double dist = std::sqrt(dist2);
            g.normal = dist > 0.0 ? Vec2(d * (1.0 / dist)) : Vec2(0.0, 1.0);
            g.overlap = rsum - dist;
            g.point = x1 + (r1 - 0.5 * g.overlap) * g.normal;
            v2c = vel[s2] + spinCross(spin[s2], g.point - x2);
            spin2 = spin[s2];
        } else {
            const Segment& sg = m_segments[p.end2];
            if (!segmentGeometry(p.end2, x1, r1, g)) {
                // The ball is in a neighbouring segment's region: that segment holds the contact.
                if (p.active) endContact(p, m_cold[i], false);
                if ((m_ball_moved[s1] | m_segment_moved[p.end2]) && !b.fat[s1].overlaps(sg.fat))
                    m_to_remove.push_back(static_cast<uint32_t>(i));
                continue;
            }
            const WallData& wall = m_walls[sg.wall];
            x2 = wall.center;
            v2c = wall.vel + spinCross(wall.spin, g.point - x2);
            spin2 = wall.spin;
            if (!p.active && g.overlap <= -p.activity) {
                if constexpr (kAuto) {
                    const Vec2 a1 = (force[s1] + b.fapp[s1]) * b.inv_mass[s1] + m_gravity;
                    noteApproach(p, m_cold[i], -g.overlap, v2c - vel[s1], a1.norm(), g.normal);
                }
                if ((m_ball_moved[s1] | m_segment_moved[p.end2]) && !b.fat[s1].overlaps(sg.fat))
                    m_to_remove.push_back(static_cast<uint32_t>(i));
                continue;
            }
        }

        // ---- the pair is a contact this step
        const double mass_eff = p.mass_eff;
        const Vec2 r1c = g.point - x1;
        const Vec2 v1c = vel[s1] + spinCross(spin[s1], r1c);
        const Vec2 vrel = v2c - v1c;
        const Vec2 t = perp(g.normal);
        bool first = false;
        if (!p.active) {
            first = true;
            activate(p, m_cold[i], g, vrel);
        }
        fd.flags = (first ? kFdFirstCall : 0u) | (kEnergy ? kFdEnergyOn : 0u);
        fd.status = 0;
        fd.u_n = g.overlap;
        fd.u_dot_n = -vrel.dot(g.normal);
        fd.u_dot_s = vrel.dot(t);
        fd.t_dot_rel = spin2 - spin[s1];
        fd.du_n = fd.u_dot_n * dt;
        fd.du_s = fd.u_dot_s * dt;
        fd.dtheta = fd.t_dot_rel * dt;
        fd.mass_eff = mass_eff;
        fd.inv_mass_eff_s = p.inv_mass_eff_s;
        const double fn_old = p.n_force, fs_old = p.s_force, m_old = p.moment;
        fd.n_force = fn_old;
        fd.s_force = fs_old;
        fd.moment = m_old;
        fd.knest = fd.ksest = fd.krest = 0.0;
        if constexpr (kEnergy)
            for (double& e : fd.energy) e = 0.0;

        try {
            p.model->FDlaw(fd);
        } catch (const std::exception& e) {
            // A model without the SDK's barrier threw (docs/plugin-abi.md, "Exceptions").
            fd.status = 1;
            m_plugin_error = e.what();
            fd.error = m_plugin_error.c_str();
        } catch (...) {
            fd.status = 1;
            fd.error = "unknown exception";
        }
        if (fd.status != 0) reportFailedLaw(p, fd);
        // Non-finite output: summed here, checked once after the loop (findNonFiniteContact).
        finite_check += fd.n_force + fd.s_force + fd.moment + fd.knest + fd.ksest;

        // ---- forces onto the ends
        const Vec2 f = fd.n_force * g.normal + fd.s_force * t;
        force[s1] -= f;
        moment[s1] -= cross(r1c, f) + fd.moment;
        if (!p.wall) {
            force[p.end2] += f;
            moment[p.end2] += cross(g.point - x2, f) + fd.moment;
        } else {
            WallData& w = m_walls[m_segments[p.end2].wall];
            w.force += f;
            w.moment += cross(g.point - w.center, f) + fd.moment;
        }

        // ---- extras
        const bool ends =
            g.overlap <= -p.activity && !(fd.flags & kFdKeep) && p.model->OKToDelete();
        if constexpr (kAuto || kEnergy || kGuard) {
            PairCold& c = m_cold[i];
            if constexpr (kAuto) {
                c.krest = fd.krest;
                noteContact(p, c, fd.knest, fd.ksest, fd.krest, r1c.squaredNorm(),
                            p.wall ? 0.0 : (g.point - x2).squaredNorm(), mass_eff,
                            (fd.flags & kFdBonded) == 0);
            }
            if constexpr (kEnergy) {
                m_energy_acc.slip += fd.energy[kEnergySlip];
                m_energy_acc.dashpot += fd.energy[kEnergyDashpot];
                m_energy_acc.plastic += fd.energy[kEnergyPlastic];
                // A break releases what the bond held (accuracy-reference 3.6, pitfall 2; the
                // model says how much), and so does the end of a contact that is still loaded.
                m_energy_acc.released += fd.energy[kEnergyReleased];
                c.strain = fd.energy[kEnergyStrain];
                c.bond = fd.energy[kEnergyBondStrain];
                if (ends) {
                    m_energy_acc.released += c.strain + c.bond;
                } else {
                    strain_now += c.strain;
                    bond_now += c.bond;
                }
            }
        }

        if constexpr (kGuard) {
            // The guard follows a contact through its first kGuardWatch steps, which covers any
            // resolved impact (30 to 150 steps); a contact that persists longer (a packing) is
            // not followed further, and its energy check is skipped (docs/physics/guard.md).
            if (p.steps < kGuardWatch) {
                // Energy the contact took from the bodies: the impulse of each step's force
                // times the mean of the half-step rates around it, which is what the law of
                // motion did with it. The two halves are booked at the two FDlaw calls the force
                // spans, each with the rate it sees: the previous force over this window, the
                // new force over this step as the estimate of its window (exact for a constant
                // step). So no rate is kept, and nothing outside the hot pair is touched.
                const double power_old =
                    fn_old * fd.u_dot_n - fs_old * fd.u_dot_s - m_old * fd.t_dot_rel;
                const double power_new =
                    fd.n_force * fd.u_dot_n - fd.s_force * fd.u_dot_s - fd.moment * fd.t_dot_rel;
                p.work += 0.5 * (m_window * power_old + dt * power_new);
                if (ends) p.work += 0.5 * dt * power_new;  // the rest of the last force's work
                p.work_peak = std::max(p.work_peak, p.work);
                // The deepest overlap is where the overlap stops growing: note the previous
                // step's values there, once per turn (the stiffness and resolution checks).
                const bool growing = first || g.overlap > p.overlap;
                if (!growing && p.loading) noteDeepest(p, m_cold[i], fn_old, fd.u_dot_n);
                p.loading = growing;
            }
            // A contact that was pushing the bodies apart cannot reverse its normal within a
            // step unless one body went through the other (a model exerting no force may let
            // it). One step back the centre line ran the other way if the bodies separated, in
            // the current normal's frame, by more than the distance from the ball's centre to
            // the other body's centre or wall line: -du_n > that distance.
            // Checked at every step of an impact, and in a persistent contact once it overlaps
            // by more than a tenth of the ball's radius.
            if (!first && fn_old > 0.0 && (p.steps < kGuardWatch || g.overlap > 0.1 * r1) &&
                -fd.du_n > (p.wall ? r1 : r1 + radius[p.end2]) - g.overlap)
                reportPassThrough(p, g);
        }
        p.n_force = fd.n_force;
        p.s_force = fd.s_force;
        p.moment = fd.moment;
        p.overlap = g.overlap;
        p.knest = fd.knest;
        p.ksest = fd.ksest;
        p.sliding = (fd.flags & kFdSliding) != 0;
        p.bonded = (fd.flags & kFdBonded) != 0;
        p.steps += g.overlap > 0.0;
        if (fd.flags & kFdBroken) queueBreak(i, g.point, fd.break_mode);
        if (ends) {
            endContact(p, m_cold[i], kGuard);
            // Its ends may have moved apart while it was a contact (inactive pairs are checked
            // only when an end is re-inserted).
            const Box& fat2 = p.wall ? m_segments[p.end2].fat : b.fat[p.end2];
            if (!b.fat[s1].overlaps(fat2)) m_to_remove.push_back(static_cast<uint32_t>(i));
        }
    }

    if (!std::isfinite(finite_check)) findNonFiniteContact();
    for (auto it = m_to_remove.rbegin(); it != m_to_remove.rend(); ++it) removePair(*it);
    clearMovedFlags();
    if constexpr (kEnergy) {
        m_energy_acc.strain = strain_now;
        m_energy_acc.bond = bond_now;
    }
}

// The rare paths of the loop, kept out of it so that its body stays small.

void Model::activate(Pair& p, PairCold& c, const ContactGeometry& g, const Vec2& vrel) {
    if (c.rules_version != m_rules_version) refreshRule(p);
    p.active = true;
    ++m_profile.contacts_created;
    c.duration = p.model->ContactDuration(p.mass_eff, std::max(0.0, -vrel.dot(g.normal)));
    // For the guard: a contact born overlapping (placed so) gives back energy it never took.
    const double approach = -vrel.dot(g.normal);
    c.approach_rate = std::max(approach, 0.0);
    c.born_overlapped = g.overlap > std::max(approach * m_dt, 0.0) * (1.0 + 1e-9) + 1e-15;
    if (m_contact_events) {
        Event ev;
        ev.kind = EventKind::ContactCreated;
        ev.time = m_time;
        ev.pos = g.point;
        ev.contact = ContactKey{c.key};
        ev.model = p.rule->model_name;
        m_events.push_back(std::move(ev));
    }
}

void Model::noteDeepest(const Pair& p, PairCold& c, double force, double rate_after) {
    if (p.overlap <= c.overlap_max) return;
    c.overlap_max = p.overlap;
    c.force_at_max = force;
    c.rate_at_max = rate_after;
    c.knest_at_max = p.knest;
    c.dt_at_max = m_dt;
}

void Model::queueBreak(std::size_t i, const Vec2& point, int32_t mode) {
    Event ev;
    ev.kind = EventKind::BondBreak;
    ev.time = m_time;
    ev.pos = point;
    ev.contact = ContactKey{m_cold[i].key};
    ev.mode = mode;
    ev.model = m_pairs[i].rule->model_name;
    m_events.push_back(std::move(ev));
}

void Model::reportFailedLaw(const Pair& p, const FdBlock& fd) const {
    throw PluginError("contact model '" + p.rule->model_name + "' failed at step " +
                      std::to_string(m_step) + " on " + describePair(p) + ": " +
                      (fd.error ? fd.error : "(no message)"));
}

void Model::findNonFiniteContact() const {
    // The force loop only sums the models' outputs; find the first contact that made the sum
    // non-finite (its stored values are this step's).
    for (const Pair& p : m_pairs)
        if (p.active && !std::isfinite(p.n_force + p.s_force + p.moment + p.knest + p.ksest))
            throwNonFinite(describePair(p) + ": FDlaw returned normal force " + num(p.n_force) +
                           ", shear force " + num(p.s_force) + ", moment " + num(p.moment) +
                           ", knest " + num(p.knest) + ", ksest " + num(p.ksest) + " at overlap " +
                           num(p.overlap));
    throwNonFinite(
        "a contact model returned a non-finite value (the contact ended in the same step)");
}

void Model::reportPassThrough(const Pair& p, const ContactGeometry& g) const {
    throw NumericalError(
        "at step " + std::to_string(m_step) + " (t = " + num(m_time) + " s): " + describePair(p) +
        ": the contact normal reversed within one step, so one body passed "
        "through the other (overlap " +
        num(g.overlap) + " m); the contact is too soft for this impact or the step too large");
}

void Model::endContact(Pair& p, PairCold& c, bool check_guard) {
    if (check_guard && p.steps > 0 && p.steps <= kGuardWatch) {
        // A contact created overlapping (by placement) gives back energy it never took.
        // Reference: the larger of the energy the contact held at its peak and the kinetic
        // energy of the approach (a contact that only ever gave energy has no peak).
        const double reference =
            std::max(p.work_peak, 0.5 * p.mass_eff * c.approach_rate * c.approach_rate);
        if (m_guard.energy != GuardAction::Off && !c.born_overlapped && reference > 0.0 &&
            p.work < -m_guard.energy_tolerance * reference) {
            const std::string what =
                describePair(p) + " returned " + num(-p.work) + " J more than it took (reference " +
                num(reference) + " J, tolerance " + num(100.0 * m_guard.energy_tolerance) +
                "%) over " + std::to_string(p.steps) + " steps ending at t = " + num(m_time) +
                " s; the step (" + num(m_dt) +
                " s) is too large for the model's stiffness, or the "
                "model reports too low a stiffness (knest " +
                num(p.knest) + " N/m)";
            if (m_guard.energy == GuardAction::Error)
                throw NumericalError("energy created: " + what);
            if (m_energy_gain++ == 0) m_energy_gain_first = what;
        }
        // Under-resolved: a step taken during the contact was too large for the impact's own
        // duration (the model's estimate at touch). A contact that is short for other reasons
        // (grazing, knocked away) is not a finding; a model that misreports its stiffness is the
        // stiffness check's business.
        if (m_guard.resolution != GuardAction::Off && !p.bonded &&
            c.duration < m_guard.min_steps * c.dt_at_max) {
            const std::string what = describePair(p) + " had " + num(c.duration / c.dt_at_max) +
                                     " steps per contact duration (" + num(c.duration) +
                                     " s at dt = " + num(c.dt_at_max) + " s, t = " + num(m_time) +
                                     " s); it lasted " + std::to_string(p.steps) + " steps";
            if (m_guard.resolution == GuardAction::Error)
                throw NumericalError("impact under-resolved: " + what + "; at least " +
                                     std::to_string(m_guard.min_steps) + " steps are needed");
            if (m_underresolved++ == 0) m_underresolved_first = what;
        }
        // At the deepest overlap the force may be up to twice the reported stiffness times the
        // overlap (tangent vs secant), plus what a dashpot up to critical damping gives at the
        // rate there (about zero for a resolved impact, not for a contact in a packing).
        const double secant = c.overlap_max > 0.0 ? c.force_at_max / c.overlap_max : 0.0;
        const double allowed =
            2.0 * c.knest_at_max * c.overlap_max +
            2.0 * std::sqrt(p.mass_eff * c.knest_at_max) * std::fabs(c.rate_at_max);
        if (m_guard.stiffness != GuardAction::Off && !p.bonded && c.force_at_max > allowed) {
            const std::string what =
                describePair(p) + ": at its deepest overlap its normal force was " + num(secant) +
                " N/m of overlap while it reported knest " + num(c.knest_at_max) +
                " N/m; the time step follows knest, so the model must report its true tangent "
                "stiffness (docs/plugin-abi.md, time-step contract)";
            if (m_guard.stiffness == GuardAction::Error)
                throw NumericalError("stiffness under-reported: " + what);
            if (m_stiffness_lies++ == 0) m_stiffness_lies_first = what;
        }
    }
    resetPair(p);
}

}  // namespace talus
