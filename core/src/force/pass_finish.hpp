// SPDX-License-Identifier: MIT
//
// Pass 3 of the force loop: what a pair's step leaves behind. For a contact, named stages in
// order (finishContact): its forces and moments onto both ends (the model's forces act on end 2,
// end 1 gets the opposite; torques are (contact point - centre) x force plus the model's
// moment), then, each only when the scene asks for it (a compile-time switch of LoopFeatures),
// the automatic step's notes, the energy books and the stability guard, then the law's result
// kept in the pair and a break or the contact's end. For a pair apart: the broadphase check of
// its fat boxes. How the results reach beyond the pair depends on the Delivery (view.hpp). Not
// installed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include "force/force.hpp"
#include "force/view.hpp"
#include "step/group_energy.hpp"
#include "step/step_limits.hpp"

namespace talus {

/// What a contact held one step ago, from what it holds now, what it dissipated in the step and
/// the work the bodies did on it (its force over the step's displacement, trapezoidal: exact for
/// a linear spring). Used once, when tracing starts with loaded contacts.
template <class Fd>  // FdBlock, or a kernel's KernelFd
double storedBefore(const Fd& fd, double fn_old, double fs_old, double m_old) {
    const double work = 0.5 * ((fn_old + fd.n_force) * fd.du_n - (fs_old + fd.s_force) * fd.du_s -
                               (m_old + fd.moment) * fd.dtheta);
    return fd.energy[kEnergyStrain] + fd.energy[kEnergyBondStrain] + fd.energy[kEnergySlip] +
           fd.energy[kEnergyDashpot] + fd.energy[kEnergyPlastic] + fd.energy[kEnergyReleased] -
           work;
}

/// A law's output as an FdBlock (the energy contract's rare path takes one).
inline const FdBlock& asFdBlock(const FdBlock& fd, const FdBlock&) { return fd; }
template <class Fd>  // a kernel's KernelFd
FdBlock asFdBlock(const Fd& r, const FdBlock& tmpl) {
    FdBlock fd = tmpl;
    fd.flags = r.flags;
    fd.u_n = r.u_n, fd.u_dot_n = r.u_dot_n, fd.u_dot_s = r.u_dot_s, fd.t_dot_rel = r.t_dot_rel;
    fd.du_n = r.du_n, fd.du_s = r.du_s, fd.dtheta = r.dtheta;
    fd.n_force = r.n_force, fd.s_force = r.s_force, fd.moment = r.moment;
    fd.knest = r.knest, fd.ksest = r.ksest, fd.krest = r.krest;
    for (int e = 0; e < kEnergyCount; ++e) fd.energy[e] = r.energy[e];
    return fd;
}

/// What one contact adds to the books, in the order one thread adds it (PairEnergy).
__attribute__((always_inline)) inline void bookPairEnergy(EnergyBooks& books, ForceSums& sums,
                                                          const PairEnergy& pe) {
    if (pe.what & PairEnergy::kPlacement) books.acc.placement += pe.placement;
    if (pe.what & PairEnergy::kContact) {
        books.acc.slip += pe.slip;
        // The dashpot impulse spans the velocity window around this step: booked at the next
        // energy snapshot, half before it (law_of_motion.cpp).
        books.dashpot_pending += pe.dashpot;
        books.acc.plastic += pe.plastic;
        books.acc.released += pe.released;
    }
    if (pe.what & PairEnergy::kHeld) sums.held_before += pe.held;
    if (pe.what & (PairEnergy::kEnds | PairEnergy::kHandOver))
        books.acc.released += pe.released_end;
    if (pe.what & PairEnergy::kStored) {
        sums.strain_now += pe.strain;
        sums.bond_now += pe.bond;
    }
}

/// Whether a finish adds onto `ball` at once: always on one thread, never in the threads' serial
/// part (it records), in a thread's range where the thread owns the ball (its route).
template <Delivery kMode>
inline bool addsAtOnce(const ForceView& v, const ForceThreadPart& part, uint32_t ball) {
    if constexpr (kMode == Delivery::Parallel) return v.route[ball] == part.index;
    return kMode == Delivery::Direct;
}

/// Pass 3 for a pair that is not a contact this step (Apart or Elsewhere).
template <class Features, Delivery kMode>
__attribute__((always_inline)) inline void finishApart(const ForceView& v, std::size_t i,
                                                       PairStep step, ForceThreadPart& part) {
    const Pair& p = v.pairs[i];
    if constexpr (kMode != Delivery::Direct) {
        // Nothing for the gather to add (-0.0 adds nothing) at an end a thread does not own.
        for (int end = 0; end < (p.wall ? 1 : 2); ++end) {
            if (addsAtOnce<kMode>(v, part, end ? p.end2 : p.end1)) continue;
            std::fill(v.actions[i].add[end], v.actions[i].add[end] + 3, -0.0);
            if constexpr (Features::kAuto)
                std::fill(v.stiffness[i].add[end], v.stiffness[i].add[end] + 2, -0.0);
        }
        if constexpr (Features::kEnergy) v.energies[i].what = 0;
    }
    // The approach limit needs the step's complete forces: noted after the loop.
    if constexpr (Features::kAuto)
        if (step == PairStep::Apart) part.apart.push_back(static_cast<uint32_t>(i));
    const uint32_t s1 = p.end1;
    const bool moved = p.wall ? (v.ball_moved[s1] | v.segment_moved[p.end2]) != 0
                              : (v.ball_moved[s1] | v.ball_moved[p.end2]) != 0;
    if (moved && !v.fat[s1].overlaps(p.wall ? v.segments[p.end2].fat : v.fat[p.end2])) {
        if constexpr (kMode == Delivery::Parallel)
            part.items.push_back({static_cast<uint32_t>(i), Deferred::Remove});
        else
            v.to_remove.push_back(static_cast<uint32_t>(i));
    }
}

/// A contact that ended, after the rest of its finish: a fresh model object for its next touch,
/// and the broadphase check its ends may need (inactive pairs are checked only when an end is
/// re-inserted, and its ends may have moved apart while it was a contact).
template <class Features>
void endAndCheck(const ForceView& v, std::size_t i) {
    Pair& p = v.pairs[i];
    endContact(v.world, p, v.cold[i], Features::kGuard);
    const Box& fat2 = p.wall ? v.segments[p.end2].fat : v.fat[p.end2];
    if (!v.fat[p.end1].overlaps(fat2)) v.to_remove.push_back(static_cast<uint32_t>(i));
}

/// A contact's step as the finish's stages read it: pass 1's geometry, the law's forces of the
/// last step, and what the first stage computed.
struct ContactStep {
    const PairEntry& e;
    double fn_old, fs_old, m_old;  // the law's forces one step ago
    bool first;                    // its first step in contact
    bool placement;                // ... and born overlapping (placement energy)
    double closure;                // ... the overlap its first step made (Touch)
    double placed = 0.0;           // the placement energy
    bool ends = false;             // it separates beyond its activity distance and ends
    Vec2 force{0.0, 0.0};          // on end 2 (end 1 gets -force)
    Vec2 arm1{0.0, 0.0};           // contact point - end 1's centre
};

/// Stage 0: a failed law stops the run; a first touch born overlapping books its placement; the
/// outputs' sum for the check after the loop (findNonFiniteContact).
template <class Features, class Fd>
__attribute__((always_inline)) inline void checkLawOutput(const ForceView& v, std::size_t i,
                                                          const Fd& fd, ContactStep& cs,
                                                          ForceThreadPart& part) {
    if constexpr (std::is_same_v<Fd, FdBlock>) {  // (a kernel reports no failure, no first touch)
        if (fd.status != 0) reportFailedLaw(v.world, v.pairs[i], fd);
        if (cs.placement)
            cs.placed = notePlacement(v.world, v.pairs[i], cs.closure, cs.e.g.overlap, fd,
                                      Features::kEnergy);
    }
    part.finite_check += fd.n_force + fd.s_force + fd.moment + fd.knest + fd.ksest;
}

/// Stage 1: the forces onto the ends (with threads: onto a ball at once where the thread owns it,
/// else recorded for the gather); a wall gets its force, moment and stiffness.
template <Delivery kMode, class Fd>
__attribute__((always_inline)) inline void applyForces(const ForceView& v, std::size_t i,
                                                       const Fd& fd, ContactStep& cs,
                                                       const ForceThreadPart& part) {
    const Pair& p = v.pairs[i];
    const ContactGeometry& g = cs.e.g;
    const uint32_t s1 = p.end1;
    cs.arm1 = g.point - v.pos[s1];
    const Vec2 f = fd.n_force * g.normal + fd.s_force * perp(g.normal);
    cs.force = f;
    const double moment1 = cross(cs.arm1, f) + fd.moment;
    if (addsAtOnce<kMode>(v, part, s1)) {
        v.force[s1] -= f;
        v.moment[s1] -= moment1;
    } else {
        double* add = v.actions[i].add[0];
        add[0] = -f.x(), add[1] = -f.y(), add[2] = -moment1;
    }
    if (!p.wall) {
        const double moment2 = cross(g.point - cs.e.x2, f) + fd.moment;
        if (addsAtOnce<kMode>(v, part, p.end2)) {
            v.force[p.end2] += f;
            v.moment[p.end2] += moment2;
        } else {
            double* add = v.actions[i].add[1];
            add[0] = f.x(), add[1] = f.y(), add[2] = moment2;
        }
    } else {
        // (wall pairs are the serial part's alone when threads run)
        WallData& w = v.walls[v.segments[p.end2].wall];
        w.force += f;
        w.moment += cross(g.point - w.center, f) + fd.moment;
        w.knest += fd.knest;
    }
}

/// Whether the contact ends this step: separated beyond its activity distance, and its model
/// agrees. (The activity distance is >= 0: a contact that overlaps goes on, its cold record
/// unread.)
template <class Fd>
__attribute__((always_inline)) inline bool contactEnds(const ForceView& v, std::size_t i,
                                                       const Fd& fd, const ContactStep& cs) {
    const double overlap = cs.e.g.overlap;
    return overlap <= 0.0 && overlap <= -v.cold[i].activity && !(fd.flags & kFdKeep) &&
           v.pairs[i].model->OKToDelete();
}

/// Stage 2 (the automatic step): the stiffness sums of both ends (timestep.cpp's stability rule,
/// per ball) and the contact's limits.
template <Delivery kMode, class Fd>
__attribute__((always_inline)) inline void noteStepLimits(const ForceView& v, std::size_t i,
                                                          const Fd& fd, const ContactStep& cs,
                                                          ForceThreadPart& part) {
    const Pair& p = v.pairs[i];
    PairCold& c = v.cold[i];
    c.krest = fd.krest;
    auto& balls = v.world.bodies.balls;
    const double arm2_sq = p.wall ? 0.0 : (cs.e.g.point - cs.e.x2).squaredNorm();
    const double k_tran = fd.knest + fd.ksest;
    const double k_rot1 = fd.ksest * cs.arm1.squaredNorm() + fd.krest;
    const double k_rot2 = fd.ksest * arm2_sq + fd.krest;
    if (addsAtOnce<kMode>(v, part, p.end1))
        balls.k_tran[p.end1] += k_tran, balls.k_rot[p.end1] += k_rot1;
    else
        v.stiffness[i].add[0][0] = k_tran, v.stiffness[i].add[0][1] = k_rot1;
    if (!p.wall) {
        if (addsAtOnce<kMode>(v, part, p.end2))
            balls.k_tran[p.end2] += k_tran, balls.k_rot[p.end2] += k_rot2;
        else
            v.stiffness[i].add[1][0] = k_tran, v.stiffness[i].add[1][1] = k_rot2;
    }
    noteContactLimits(v.world, p, c, fd.knest, c.mass_eff, part.limits);
}

/// Stage 3 (energy tracing): the law's energies against the ABI's contract, into the books (one
/// thread: at once; threads: the pair's PairEnergy, added in pair order after the loop), the
/// stored energies it holds now, and the group shares.
template <Delivery kMode, class Fd>
__attribute__((always_inline)) inline void bookContactEnergy(const ForceView& v, ForceSums& sums,
                                                             std::size_t i, const Fd& fd,
                                                             const ContactStep& cs,
                                                             ForceThreadPart& part) {
    World& world = v.world;
    const Pair& p = v.pairs[i];
    PairStored& stored = v.stored[i];
    // The plugin's partitions against the ABI's contract (rare path when broken): every
    // partition finite (x - x is 0 only for a finite x) and no dissipation negative. Only with
    // finite kinematics: a state already non-finite is the engine's to report
    // (findNonFiniteContact, the law of motion), not the plugin's fault.
    const double energy_sum =
        fd.energy[0] + fd.energy[1] + fd.energy[2] + fd.energy[3] + fd.energy[4] + fd.energy[5];
    if (!(energy_sum - energy_sum == 0.0 && fd.energy[kEnergySlip] >= 0.0 &&
          fd.energy[kEnergyDashpot] >= 0.0 && fd.energy[kEnergyPlastic] >= 0.0) &&
        std::isfinite(fd.u_n + fd.du_n + fd.du_s + fd.dtheta)) {
        if constexpr (kMode == Delivery::Parallel) {
            DeferredItem item{static_cast<uint32_t>(i), Deferred::Contract};
            item.flags = static_cast<uint32_t>(part.contracts.size());
            part.items.push_back(item);
            part.contracts.push_back({asFdBlock(fd, v.fd_template), cs.fn_old, cs.fs_old, cs.m_old,
                                      stored.strain, stored.bond});
        } else {
            checkEnergyContract(world, p, stored.strain, stored.bond, asFdBlock(fd, v.fd_template),
                                cs.fn_old, cs.fs_old, cs.m_old, v.totals_before);
        }
    }
    // A break releases what the bond held (Potyondy & Cundall 2004; the model says how much),
    // and so does the end of a contact that is still loaded.
    stored.strain = fd.energy[kEnergyStrain];
    stored.bond = fd.energy[kEnergyBondStrain];
    double held = 0.0;
    const bool baseline = world.books.strain_baseline_pending && !cs.first;
    if (baseline) held = storedBefore(fd, cs.fn_old, cs.fs_old, cs.m_old);
    if constexpr (kMode == Delivery::Direct) {
        // Into the books at once, in the order bookPairEnergy adds a PairEnergy.
        EnergyBooks& books = world.books;
        if (cs.placement) books.acc.placement += cs.placed;
        books.acc.slip += fd.energy[kEnergySlip];
        // The dashpot impulse spans the velocity window around this step: booked at the next
        // energy snapshot, half before it (law_of_motion.cpp).
        books.dashpot_pending += fd.energy[kEnergyDashpot];
        books.acc.plastic += fd.energy[kEnergyPlastic];
        books.acc.released += fd.energy[kEnergyReleased];
        if (baseline) sums.held_before += held;
        if (cs.ends) {
            books.acc.released += stored.total();
        } else {
            sums.strain_now += stored.strain;
            sums.bond_now += stored.bond;
        }
    } else {
        PairEnergy& pe = v.energies[i];
        pe.what = PairEnergy::kContact;
        if (cs.placement) pe.what |= PairEnergy::kPlacement, pe.placement = cs.placed;
        pe.slip = fd.energy[kEnergySlip];
        pe.dashpot = fd.energy[kEnergyDashpot];
        pe.plastic = fd.energy[kEnergyPlastic];
        pe.released = fd.energy[kEnergyReleased];
        if (baseline) pe.held = held, pe.what |= PairEnergy::kHeld;
        if (cs.ends) {
            pe.released_end = stored.total();
            pe.what |= PairEnergy::kEnds;
        } else {
            pe.strain = stored.strain;
            pe.bond = stored.bond;
            pe.what |= PairEnergy::kStored;
        }
    }
    // Group shares and the work across group borders (group_energy.cpp): one branch per
    // contact, taken only with groups traced (one thread).
    if (v.groups)
        bookContactToOwnGroups(world, i, fd.energy, fd.moment, cs.placement, cs.ends, held,
                               cs.force, cs.e.g.point);
}

/// Stage 4a (the guard): the watch of a young contact, through its first kGuardWatch steps,
/// which covers any resolved impact (30 to 150 steps); a contact that persists longer (a
/// packing) is not followed further, and its energy check is skipped (docs/physics/guard.md).
/// Only a watched contact reads and writes its cold record and its watch here (the watch ends
/// after the loop: ForceThreadPart::watch_ends). Returns whether it is young.
template <class Fd>
__attribute__((always_inline)) inline bool watchYoungContact(const ForceView& v, std::size_t i,
                                                             const Fd& fd, const ContactStep& cs,
                                                             ForceThreadPart& part) {
    Pair& p = v.pairs[i];
    PairCold& c = v.cold[i];
    GuardWatch& w = v.world.contacts.watches[c.watch];
    const double overlap = cs.e.g.overlap;
    const bool young = w.steps < kGuardWatch;
    if (young) {
        // Energy the contact took from the bodies: the impulse of each step's force times the
        // mean of the half-step rates around it, which is what the law of motion did with it.
        // The two halves are booked at the two FDlaw calls the force spans, each with the rate
        // it sees: the previous force over this window, the new force over this step as the
        // estimate of its window (exact for a constant step). So no rate is kept.
        const double power_old =
            cs.fn_old * fd.u_dot_n - cs.fs_old * fd.u_dot_s - cs.m_old * fd.t_dot_rel;
        const double power_new =
            fd.n_force * fd.u_dot_n - fd.s_force * fd.u_dot_s - fd.moment * fd.t_dot_rel;
        w.work += 0.5 * (v.window * power_old + v.dt * power_new);
        if (cs.ends) w.work += 0.5 * v.dt * power_new;  // the rest of the last force's work
        w.work_peak = std::max(w.work_peak, w.work);
        // The deepest overlap is where the overlap stops growing: note the previous step's
        // values there, once per turn (the stiffness and resolution checks).
        const bool growing = cs.first || overlap > c.overlap;
        if (!growing && p.loading) noteDeepest(v.world, c, w, cs.fn_old, fd.u_dot_n);
        if (growing != p.loading) p.loading = growing;
    }
    c.overlap = overlap;
    c.knest = fd.knest;
    c.ksest = fd.ksest;
    w.steps += overlap > 0.0;
    w.apart += !(overlap > 0.0);
    // (endContact checks up to the watch.) A contact active without overlap for as many steps
    // sits in a packing, not in an impact: it leaves the watch as one that outlived it, so that
    // the loop stops reading its cold record.
    if (w.apart > kGuardWatch) w.steps = kGuardWatch + 1;
    if (w.steps > kGuardWatch && !cs.ends) {
        p.watched = false;
        part.watch_ends.push_back(static_cast<uint32_t>(i));
    }
    return young;
}

/// Stage 4b (the guard): a contact that was pushing the bodies apart cannot reverse its normal
/// within a step unless one body went through the other (a model exerting no force may let
/// it). One step back the centre line ran the other way if the bodies separated, in the current
/// normal's frame, by more than the distance from the ball's centre to the other body's centre
/// or wall line: -du_n > that distance. Checked at every step of an impact, and in a persistent
/// contact once it overlaps by more than a tenth of the ball's radius. (Young or deep first,
/// written out: it rules out nearly every contact of a packing in one comparison, and the
/// compiler keeps a condition's order of floating comparisons.)
template <class Fd>
__attribute__((always_inline)) inline void checkPassThrough(const ForceView& v, std::size_t i,
                                                            const Fd& fd, const ContactStep& cs,
                                                            bool young) {
    const Pair& p = v.pairs[i];
    const double overlap = cs.e.g.overlap;
    const double r1 = v.radius[p.end1];
    const bool young_or_deep = young || overlap > 0.1 * r1;
    if (young_or_deep && !cs.first && cs.fn_old > 0.0 &&
        -fd.du_n > (p.wall ? r1 : r1 + v.radius[p.end2]) - overlap)
        reportPassThrough(v.world, p, cs.e.g);
}

/// Stage 5: the law's result kept in the pair: its forces and flags, and, for the automatic step
/// and the messages (findNonFiniteContact names a contact by them), its estimates; without the
/// automatic step they are left as they were, and the step's survey asks the models when it is
/// switched on (timestep.cpp, surveyPairs).
template <class Features, class Fd>
__attribute__((always_inline)) inline void keepLawResult(const ForceView& v, std::size_t i,
                                                         const Fd& fd, const ContactStep& cs) {
    Pair& p = v.pairs[i];
    p.n_force = fd.n_force;
    p.s_force = fd.s_force;
    p.moment = fd.moment;
    // (flags written only when they change: each write of a bit is a read-modify-write; one
    // test for both, as nearly every contact of a pack sticks, unbonded, step after step)
    const bool sliding = (fd.flags & kFdSliding) != 0, bonded = (fd.flags & kFdBonded) != 0;
    if ((sliding | bonded | p.sliding | p.bonded) && (sliding != p.sliding || bonded != p.bonded)) {
        p.sliding = sliding;
        p.bonded = bonded;
    }
    if (Features::kAuto || !std::isfinite(fd.knest + fd.ksest)) {
        PairCold& c = v.cold[i];
        c.knest = fd.knest;
        c.ksest = fd.ksest;
        c.overlap = cs.e.g.overlap;
    }
}

/// Stage 6: a bond that broke, a contact that ended: at once, or deferred to the threads' serial
/// part (they raise events and free or make model objects).
template <class Features, Delivery kMode, class Fd>
__attribute__((always_inline)) inline void breakOrEnd(const ForceView& v, std::size_t i,
                                                      const Fd& fd, const ContactStep& cs,
                                                      ForceThreadPart& part) {
    if constexpr (kMode == Delivery::Parallel) {
        if (fd.flags & kFdBroken) {
            DeferredItem item{static_cast<uint32_t>(i), Deferred::Break};
            item.break_mode = fd.break_mode;
            item.flags = fd.flags;
            item.point = cs.e.g.point;
            item.sigma = fd.reserved[0];
            item.tau = fd.reserved[1];
            part.items.push_back(item);
        }
        if (cs.ends) part.items.push_back({static_cast<uint32_t>(i), Deferred::End});
    } else {
        if (fd.flags & kFdBroken)
            queueBreak(v.world, i, cs.e.g.point, fd.break_mode, (fd.flags & kFdBreakStress) != 0,
                       fd.reserved[0], fd.reserved[1]);
        if (cs.ends) endAndCheck<Features>(v, i);
    }
}

/// Pass 3 for a contact: its law has run on `fd`, its FdBlock or, for a contact a kernel
/// stepped, its KernelFd (the same names). `touch`: what its first touch found, at its first step
/// in contact (kNoTouch else). The stages in order; a feature that is off compiles its stage
/// away.
inline constexpr Touch kNoTouch{};
template <class Features, Delivery kMode, class Fd>
__attribute__((always_inline)) inline void finishContact(const ForceView& v, ForceSums& sums,
                                                         std::size_t i, const PairEntry& e,
                                                         const Fd& fd, const Touch& touch,
                                                         ForceThreadPart& part) {
    const Pair& p = v.pairs[i];
    ContactStep cs{e,
                   p.n_force,
                   p.s_force,
                   p.moment,
                   touch.first,
                   touch.first && touch.born_overlapped,
                   touch.closure};
    checkLawOutput<Features>(v, i, fd, cs, part);
    applyForces<kMode>(v, i, fd, cs, part);
    cs.ends = contactEnds(v, i, fd, cs);
    if constexpr (Features::kAuto) noteStepLimits<kMode>(v, i, fd, cs, part);
    if constexpr (Features::kEnergy) bookContactEnergy<kMode>(v, sums, i, fd, cs, part);
    if constexpr (Features::kGuard) {
        const bool young = p.watched && watchYoungContact(v, i, fd, cs, part);
        checkPassThrough(v, i, fd, cs, young);
    }
    keepLawResult<Features>(v, i, fd, cs);
    breakOrEnd<Features, kMode>(v, i, fd, cs, part);
}

}  // namespace talus
