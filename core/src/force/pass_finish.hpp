// SPDX-License-Identifier: MIT
//
// Pass 3 of the force loop: what a pair's step leaves behind. For a contact: its forces and
// moments onto both ends (the model's forces act on end 2, end 1 gets the opposite; torques are
// (contact point - centre) x force plus the model's moment), and, only when the scene asks for
// them, the automatic step's sums and limits, the energy books and the stability guard. For a
// pair apart: the broadphase check of its fat boxes. How the results reach beyond the pair
// depends on the Delivery (view.hpp). Not installed.
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
template <class Fd>  // FdBlock, or a lane contact's LaneResult
double storedBefore(const Fd& fd, double fn_old, double fs_old, double m_old) {
    const double work = 0.5 * ((fn_old + fd.n_force) * fd.du_n - (fs_old + fd.s_force) * fd.du_s -
                               (m_old + fd.moment) * fd.dtheta);
    return fd.energy[kEnergyStrain] + fd.energy[kEnergyBondStrain] + fd.energy[kEnergySlip] +
           fd.energy[kEnergyDashpot] + fd.energy[kEnergyPlastic] + fd.energy[kEnergyReleased] -
           work;
}

/// A law's output as an FdBlock (the energy contract's rare path takes one).
inline const FdBlock& asFdBlock(const FdBlock& fd, const FdBlock&) { return fd; }
template <class Fd>  // a lane contact's LaneResult, a kernel's KernelFd
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
inline bool addsAtOnce(const ForceView& v, const ForceThreadPart* part, uint32_t ball) {
    if constexpr (kMode == Delivery::Parallel) return v.route[ball] == part->index;
    return kMode == Delivery::Direct;
}

/// Pass 3 for a pair that is not a contact this step (Apart or Elsewhere).
template <class Features, Delivery kMode>
__attribute__((always_inline)) inline void finishApart(const ForceView& v, std::size_t i,
                                                       PairStep step, ForceThreadPart* part) {
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
    if constexpr (Features::kAuto) {
        if (step == PairStep::Apart)
            (kMode == Delivery::Parallel ? part->apart : v.apart)
                .push_back(static_cast<uint32_t>(i));
    }
    const uint32_t s1 = p.end1;
    const bool moved = p.wall ? (v.ball_moved[s1] | v.segment_moved[p.end2]) != 0
                              : (v.ball_moved[s1] | v.ball_moved[p.end2]) != 0;
    if (moved && !v.fat[s1].overlaps(p.wall ? v.segments[p.end2].fat : v.fat[p.end2])) {
        if constexpr (kMode == Delivery::Parallel)
            part->items.push_back({static_cast<uint32_t>(i), Deferred::Remove});
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

/// Pass 3 for a contact: its law has run on `fd`, its FdBlock or, for a contact a lane law
/// stepped, its LaneResult (the same names). `first`: its first step in contact.
template <class Features, Delivery kMode, class Fd>
__attribute__((always_inline)) inline void finishContact(const ForceView& v, ForceSums& sums,
                                                         std::size_t i, const PairEntry& e,
                                                         const Fd& fd, bool first,
                                                         ForceThreadPart* part) {
    constexpr bool kFdBlock = std::is_same_v<Fd, FdBlock>;
    World& world = v.world;
    Pair& p = v.pairs[i];
    const ContactGeometry& g = e.g;
    const uint32_t s1 = p.end1;
    const Vec2 x1 = v.pos[s1];
    const double r1 = v.radius[s1];
    double placed = 0.0;
    const bool placement = first && v.cold[i].born_overlapped;
    if constexpr (kFdBlock) {  // (a lane law reports no failure and runs no first touch)
        if (fd.status != 0) reportFailedLaw(world, p, fd);
        if (placement)
            placed = notePlacement(world, p, v.cold[i], g.overlap, fd, Features::kEnergy);
    }
    // Non-finite output: summed here, checked once after the loop (findNonFiniteContact).
    (kMode == Delivery::Parallel ? part->finite_check : sums.finite_check) +=
        fd.n_force + fd.s_force + fd.moment + fd.knest + fd.ksest;
    const double fn_old = p.n_force, fs_old = p.s_force, m_old = p.moment;

    // ---- forces onto the ends
    const Vec2 r1c = g.point - x1;
    const Vec2 f = fd.n_force * g.normal + fd.s_force * perp(g.normal);
    const double moment1 = cross(r1c, f) + fd.moment;
    // With threads, onto a ball at once where the thread owns it (its route), else recorded.
    const auto owned = [&](uint32_t ball) { return addsAtOnce<kMode>(v, part, ball); };
    if (owned(s1)) {
        v.force[s1] -= f;
        v.moment[s1] -= moment1;
    } else {
        double* add = v.actions[i].add[0];
        add[0] = -f.x(), add[1] = -f.y(), add[2] = -moment1;
    }
    if (!p.wall) {
        const double moment2 = cross(g.point - e.x2, f) + fd.moment;
        if (owned(p.end2)) {
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

    // ---- extras
    // (the activity distance is >= 0: a contact that overlaps goes on, its cold record unread)
    const bool ends = g.overlap <= 0.0 && g.overlap <= -v.cold[i].activity &&
                      !(fd.flags & kFdKeep) && p.model->OKToDelete();
    if constexpr (Features::kAuto || Features::kEnergy || Features::kGuard) {
        PairCold& c = v.cold[i];
        if constexpr (Features::kAuto) {
            c.krest = fd.krest;
            const double arm2_sq = p.wall ? 0.0 : (g.point - e.x2).squaredNorm();
            if constexpr (kMode == Delivery::Direct) {
                noteContact(world, p, c, fd.knest, fd.ksest, fd.krest, r1c.squaredNorm(), arm2_sq,
                            c.mass_eff);
            } else {
                // noteContact's stiffness sums, term by term, at once or for the gather
                auto& balls = world.bodies.balls;
                const double k_tran = fd.knest + fd.ksest;
                const double k_rot1 = fd.ksest * r1c.squaredNorm() + fd.krest;
                const double k_rot2 = fd.ksest * arm2_sq + fd.krest;
                if (owned(s1))
                    balls.k_tran[s1] += k_tran, balls.k_rot[s1] += k_rot1;
                else
                    v.stiffness[i].add[0][0] = k_tran, v.stiffness[i].add[0][1] = k_rot1;
                if (!p.wall) {
                    if (owned(p.end2))
                        balls.k_tran[p.end2] += k_tran, balls.k_rot[p.end2] += k_rot2;
                    else
                        v.stiffness[i].add[1][0] = k_tran, v.stiffness[i].add[1][1] = k_rot2;
                }
                noteContactLimits(
                    world, p, c, fd.knest, c.mass_eff,
                    kMode == Delivery::Parallel ? part->limits : world.stepping.limits);
            }
        }
        if constexpr (Features::kEnergy) {
            PairStored& stored = v.stored[i];
            // The plugin's partitions against the ABI's contract (rare path when broken): every
            // partition finite (x - x is 0 only for a finite x) and no dissipation negative. Only
            // with finite kinematics: a state already non-finite is the engine's to report
            // (findNonFiniteContact, the law of motion), not the plugin's fault.
            const double energy_sum = fd.energy[0] + fd.energy[1] + fd.energy[2] + fd.energy[3] +
                                      fd.energy[4] + fd.energy[5];
            if (!(energy_sum - energy_sum == 0.0 && fd.energy[kEnergySlip] >= 0.0 &&
                  fd.energy[kEnergyDashpot] >= 0.0 && fd.energy[kEnergyPlastic] >= 0.0) &&
                std::isfinite(fd.u_n + fd.du_n + fd.du_s + fd.dtheta)) {
                if constexpr (kMode == Delivery::Parallel) {
                    DeferredItem item{static_cast<uint32_t>(i), Deferred::Contract};
                    item.flags = static_cast<uint32_t>(part->contracts.size());
                    part->items.push_back(item);
                    part->contracts.push_back({asFdBlock(fd, v.fd_template), fn_old, fs_old, m_old,
                                               stored.strain, stored.bond});
                } else {
                    checkEnergyContract(world, p, stored.strain, stored.bond,
                                        asFdBlock(fd, v.fd_template), fn_old, fs_old, m_old,
                                        v.totals_before);
                }
            }
            // A break releases what the bond held (Potyondy & Cundall 2004; the model says how
            // much), and so does the end of a contact that is still loaded.
            stored.strain = fd.energy[kEnergyStrain];
            stored.bond = fd.energy[kEnergyBondStrain];
            double held = 0.0;
            const bool baseline = world.books.strain_baseline_pending && !first;
            if (baseline) held = storedBefore(fd, fn_old, fs_old, m_old);
            if constexpr (kMode == Delivery::Direct) {
                // Into the books at once, in the order bookPairEnergy adds a PairEnergy.
                EnergyBooks& books = world.books;
                if (placement) books.acc.placement += placed;
                books.acc.slip += fd.energy[kEnergySlip];
                // The dashpot impulse spans the velocity window around this step: booked at
                // the next energy snapshot, half before it (law_of_motion.cpp).
                books.dashpot_pending += fd.energy[kEnergyDashpot];
                books.acc.plastic += fd.energy[kEnergyPlastic];
                books.acc.released += fd.energy[kEnergyReleased];
                if (baseline) sums.held_before += held;
                if (ends) {
                    books.acc.released += stored.total();
                } else {
                    sums.strain_now += stored.strain;
                    sums.bond_now += stored.bond;
                }
            } else {
                PairEnergy& pe = v.energies[i];
                pe.what = PairEnergy::kContact;
                if (placement) pe.what |= PairEnergy::kPlacement, pe.placement = placed;
                pe.slip = fd.energy[kEnergySlip];
                pe.dashpot = fd.energy[kEnergyDashpot];
                pe.plastic = fd.energy[kEnergyPlastic];
                pe.released = fd.energy[kEnergyReleased];
                if (baseline) pe.held = held, pe.what |= PairEnergy::kHeld;
                if (ends) {
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
                bookContactToGroups(world, i, fd.energy, fd.moment, first, ends, held, f, g.point);
        }
    }

    if constexpr (Features::kGuard) {
        // The guard follows a contact through its first kGuardWatch steps, which covers any
        // resolved impact (30 to 150 steps); a contact that persists longer (a packing) is not
        // followed further, and its energy check is skipped (docs/physics/guard.md). Only a
        // watched contact reads and writes its cold record here.
        bool young = false;
        if (p.watched) {
            PairCold& c = v.cold[i];
            young = c.steps < kGuardWatch;
            if (young) {
                // Energy the contact took from the bodies: the impulse of each step's force
                // times the mean of the half-step rates around it, which is what the law of
                // motion did with it. The two halves are booked at the two FDlaw calls the force
                // spans, each with the rate it sees: the previous force over this window, the new
                // force over this step as the estimate of its window (exact for a constant
                // step). So no rate is kept.
                const double power_old =
                    fn_old * fd.u_dot_n - fs_old * fd.u_dot_s - m_old * fd.t_dot_rel;
                const double power_new =
                    fd.n_force * fd.u_dot_n - fd.s_force * fd.u_dot_s - fd.moment * fd.t_dot_rel;
                c.work += 0.5 * (v.window * power_old + v.dt * power_new);
                if (ends) c.work += 0.5 * v.dt * power_new;  // the rest of the last force's work
                c.work_peak = std::max(c.work_peak, c.work);
                // The deepest overlap is where the overlap stops growing: note the previous
                // step's values there, once per turn (the stiffness and resolution checks).
                const bool growing = first || g.overlap > c.overlap;
                if (!growing && p.loading) noteDeepest(world, p, c, fn_old, fd.u_dot_n);
                if (growing != p.loading) p.loading = growing;
            }
            c.overlap = g.overlap;
            c.knest = fd.knest;
            c.ksest = fd.ksest;
            c.steps += g.overlap > 0.0;
            c.apart += !(g.overlap > 0.0);
            // (endContact checks up to the watch.) A contact active without overlap for as many
            // steps sits in a packing, not in an impact: it leaves the watch as one that
            // outlived it, so that the loop stops reading its cold record.
            if (c.apart > kGuardWatch) c.steps = kGuardWatch + 1;
            if (c.steps > kGuardWatch) p.watched = false;
        }
        // A contact that was pushing the bodies apart cannot reverse its normal within a step
        // unless one body went through the other (a model exerting no force may let it). One
        // step back the centre line ran the other way if the bodies separated, in the current
        // normal's frame, by more than the distance from the ball's centre to the other body's
        // centre or wall line: -du_n > that distance. Checked at every step of an impact, and in
        // a persistent contact once it overlaps by more than a tenth of the ball's radius.
        // (Young or deep first, written out: it rules out nearly every contact of a packing in
        // one comparison, and the compiler keeps a condition's order of floating comparisons.)
        const bool young_or_deep = young || g.overlap > 0.1 * r1;
        if (young_or_deep && !first && fn_old > 0.0 &&
            -fd.du_n > (p.wall ? r1 : r1 + v.radius[p.end2]) - g.overlap)
            reportPassThrough(world, p, g);
    }
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
    // The law's estimates, for the automatic step and the messages (findNonFiniteContact names
    // a contact by them); without the automatic step they are left as they were, and the step's
    // survey asks the models when it is switched on (timestep.cpp, surveyPairs).
    if (Features::kAuto || !std::isfinite(fd.knest + fd.ksest)) {
        PairCold& c = v.cold[i];
        c.knest = fd.knest;
        c.ksest = fd.ksest;
        c.overlap = g.overlap;
    }
    if constexpr (kMode == Delivery::Parallel) {
        if (fd.flags & kFdBroken) {
            DeferredItem item{static_cast<uint32_t>(i), Deferred::Break};
            item.break_mode = fd.break_mode;
            item.flags = fd.flags;
            item.point = g.point;
            item.sigma = fd.reserved[0];
            item.tau = fd.reserved[1];
            part->items.push_back(item);
        }
        if (ends) part->items.push_back({static_cast<uint32_t>(i), Deferred::End});
    } else {
        if (fd.flags & kFdBroken)
            queueBreak(world, i, g.point, fd.break_mode, (fd.flags & kFdBreakStress) != 0,
                       fd.reserved[0], fd.reserved[1]);
        if (ends) endAndCheck<Features>(v, i);
    }
}

}  // namespace talus
