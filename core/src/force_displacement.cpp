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
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <thread>

#include "body_store.hpp"
#include "contact_store.hpp"
#include "model_internal.hpp"
#include "narrowphase.hpp"
#include "talus/errors.hpp"
#include "talus/sdk/dashpot.hpp"

#ifdef TALUS_HAVE_OPENMP
#include <omp.h>
#endif

namespace talus {

namespace {

constexpr std::size_t kPrefetchAhead = 4;
/// Spins of a waiting thread between yields (threads, below).
constexpr int kSpinsBeforeYield = 64;

void spinPause() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

/// The law of one contact through the vtable (a model without a batched law, or a rare pair).
/// A model without the SDK's barrier may throw (docs/plugin-abi.md, "Exceptions"): caught here,
/// its text kept in `error` (the block's: each thread has its own).
void callLaw(ContactModel* model, FdBlock& fd, std::string& error) {
    try {
        model->FDlaw(fd);
    } catch (const std::exception& e) {
        fd.status = 1;
        error = e.what();
        fd.error = error.c_str();
    } catch (...) {
        fd.status = 1;
        fd.error = "unknown exception";
    }
}
/// Steps in contact the guard follows a contact for (docs/physics/guard.md).
constexpr uint32_t kGuardWatch = 400;

/// What a contact held one step ago, from what it holds now, what it dissipated in the step and
/// the work the bodies did on it (its force over the step's displacement, trapezoidal: exact for
/// a linear spring). Used once, when tracing starts with loaded contacts.
double storedBefore(const FdBlock& fd, double fn_old, double fs_old, double m_old) {
    const double work = 0.5 * ((fn_old + fd.n_force) * fd.du_n - (fs_old + fd.s_force) * fd.du_s -
                               (m_old + fd.moment) * fd.dtheta);
    return fd.energy[kEnergyStrain] + fd.energy[kEnergyBondStrain] + fd.energy[kEnergySlip] +
           fd.energy[kEnergyDashpot] + fd.energy[kEnergyPlastic] + fd.energy[kEnergyReleased] -
           work;
}

std::string num(double v) { return messageNumber(v); }

/// Why the energy partitions of one FDlaw break the ABI's contract (docs/plugin-abi.md,
/// "Energies"), or empty. Every partition must be finite. Dissipation (slip, dashpot, plastic)
/// cannot be negative in total, but a single step's increment may be: the shipped models book
/// the trapezoidal work of the leapfrog's forces minus the change of the stored energy, so the
/// quadrature error of the time integration (O(dt^2), either sign; measured up to 0.5% of the
/// step's energy scale for `power` and `hysdamp` at 30 steps per impact) and the settling of the
/// last half step at separation land in these items, which keeps the balance closed. So the
/// check is on the run's total of each kind (`totals`, before this step): it may not fall below
/// zero by more than 1% (the guard's default energy tolerance) of the energy scale `scale`
/// (stored energies before and after, |F| |du| of every component, and the total itself).
/// The rare path: called only when an increment is < 0 or a sum is not finite.
std::string energyContractViolation(const FdBlock& fd, double scale, const double* totals) {
    static const char* const names[kEnergyCount] = {"strain",  "slip",        "dashpot",
                                                    "plastic", "bond_strain", "released"};
    for (int k = 0; k < kEnergyCount; ++k)
        if (!std::isfinite(fd.energy[k]))
            return std::string("energy partition '") + names[k] + "' is " + num(fd.energy[k]);
    for (int k : {kEnergySlip, kEnergyDashpot, kEnergyPlastic}) {
        const double total = totals[k];
        // (1e-300 J: an absolute floor, so that subnormal round-off is not a breach)
        if (total + fd.energy[k] < -0.01 * (scale + std::fabs(total)) - 1e-300)
            return std::string("negative ") + names[k] + " energy increment " + num(fd.energy[k]) +
                   " J takes the run's total " + names[k] + " dissipation to " +
                   num(total + fd.energy[k]) +
                   " J (dissipation is >= 0; the step's energy scale is " + num(scale) + " J)";
    }
    return {};
}

}  // namespace

void Model::forceDisplacement() {
    const bool automatic = m_timestep.automatic;
    const bool guard = m_guard.energy != GuardAction::Off ||
                       m_guard.resolution != GuardAction::Off ||
                       m_guard.stiffness != GuardAction::Off;
    // Dispatch once per step to the loop compiled for exactly what this scene needs.
    if (automatic) {
        if (m_books.on)
            guard ? forceLoop<true, true, true>() : forceLoop<true, true, false>();
        else
            guard ? forceLoop<true, false, true>() : forceLoop<true, false, false>();
    } else {
        if (m_books.on)
            guard ? forceLoop<false, true, true>() : forceLoop<false, true, false>();
        else
            guard ? forceLoop<false, false, true>() : forceLoop<false, false, false>();
    }
}

// Every pair goes through three passes:
//   1. geometry: the pair's narrowphase and, for a contact, its FdBlock (no side effects);
//   2. the law: the model's batched FDlaw, or FDlaw;
//   3. finish, in pair order: forces onto the ends, the time-step notes, the books, the guard.
// One thread runs them pair after pair (serialRange). Threads run them in blocks of kBlock pairs
// (passes 1 and 2 of a block on any thread, the batched law once per run of contacts of one
// model; pass 3 on thread 0, block after block). A pair whose processing reaches beyond itself
// (a contact to activate, a wall contact crossing a vertex to its neighbour's pair) is processed
// alone, after everything before it. So every pair's pass 3 runs after the earlier pairs'
// (partial force sums, lists, events and sums are built in pair order), and the result is bit
// for bit the same for any thread count and with or without the batched law
// (docs/architecture.md, "Force-displacement").
template <bool kAuto, bool kEnergy, bool kGuard>
void Model::forceLoop() {
    // References to the stores' arrays, taken once: the loop body reads them as it read the
    // members they were before the stores existed (no extra load per pair).
    auto& b = m_bodies->balls;
    auto& walls = m_bodies->walls;
    const auto& segments = m_bodies->segments;
    auto& pairs = m_contacts->pairs;
    auto& cold = m_contacts->cold;
    const auto& ball_moved = m_contacts->ball_moved;
    const auto& segment_moved = m_contacts->segment_moved;
    auto& to_remove = m_contacts->to_remove;
    std::fill(b.force.begin(), b.force.end(), Vec2::Zero());
    std::fill(b.moment.begin(), b.moment.end(), 0.0);
    for (auto& w : walls) w.force.setZero(), w.moment = 0.0, w.knest = 0.0;
    if constexpr (kAuto) {
        std::fill(b.k_tran.begin(), b.k_tran.end(), 0.0);
        std::fill(b.k_rot.begin(), b.k_rot.end(), 0.0);
        m_limits = StepLimits{};
        m_limits_stale = false;
    }
    const double dt = m_dt;
    FdBlock fd_template = m_fd_template;
    fd_template.tdel = dt;
    fd_template.time = m_time;
    fd_template.flags = kEnergy ? kFdEnergyOn : 0u;
    double strain_now = 0.0, bond_now = 0.0;
    double held_before = 0.0;  // stored by contacts older than the tracing (baseline, once)
    double finite_check = 0.0;
    to_remove.clear();
    const bool groups = kEnergy && m_books.groups.on;
    if (groups) groupForceLoopStart();
    const Vec2* pos = b.pos.data();
    const Vec2* vel = b.vel.data();
    const double* radius = b.radius.data();
    const double* spin = b.spin.data();
    Vec2* force = b.force.data();
    double* moment = b.moment.data();
    const bool batched = m_batched_law;

    // ---- pass 1: the geometry of pair i into `e` and, for a contact, its FdBlock `fd`
    auto geometry = [&](std::size_t i, BlockEntry & e, FdBlock & fd) __attribute__((always_inline))
                        ->PairStep {
        const Pair& p = pairs[i];
        const uint32_t s1 = p.end1;
        const Vec2 x1 = pos[s1];
        const double r1 = radius[s1];
        ContactGeometry& g = e.g;
        Vec2 v2c;
        double spin2;
        double shear_mid = 0.0;  // ball-ball: the shear rate's half-step correction (below)
        if (!p.wall) {
            const uint32_t s2 = p.end2;
            const Vec2 x2 = pos[s2];
            const Vec2 d = x2 - x1;
            const double rsum = r1 + radius[s2];
            const double dist2 = d.squaredNorm();
            const double reach = rsum + p.activity;
            if (!p.active && dist2 >= reach * reach) return PairStep::Apart;
            const double dist = std::sqrt(dist2);
            g.normal = dist > 0.0 ? Vec2(d * (1.0 / dist)) : Vec2(0.0, 1.0);
            g.overlap = rsum - dist;
            g.point = x1 + (r1 - 0.5 * g.overlap) * g.normal;
            e.x2 = x2;
            v2c = vel[s2] + spinCross(spin[s2], g.point - x2);
            spin2 = spin[s2];
            // The shear rate at the half step. The centre line's sweep dv . t, seen from the new
            // normal, is |d_old| sin(dphi) / dt (the chord of the step), while the spin terms
            // use the new arms, which sum to |d_new|. When the distance changes as the line
            // turns (a rotating bonded cluster breathing under its centripetal load), the
            // difference (|d_old| - |d_new|) dphi / dt feeds the normal motion into the shear
            // spring: a one-sided coupling that does net work over each oscillation and pumps
            // energy in at a rate O(dt) (issue 6: a spinning bonded ring of three balls blew
            // up). Both at the half step, mean length (|d_old| + |d_new|) / 2 and mean arms,
            // cancel it to second order: u_dot_s += -(q/2) (dv.t / |d_old| + (w1 + w2) / 2)
            // with q = |d_old| - |d_new| (docs/plugin-abi.md, u_dot_s).
            const Vec2 dv = vel[s2] - vel[s1];
            const double dist_old = (d - dv * dt).norm();
            if (dist_old > 0.0) {
                const double q = dist_old - dist;
                shear_mid =
                    -0.5 * q * (dv.dot(perp(g.normal)) / dist_old + 0.5 * (spin[s1] + spin[s2]));
            }
        } else {
            // The ball is in a neighbouring segment's region: that segment holds the contact.
            if (!segmentGeometry(p.end2, x1, r1, g))
                return p.active ? PairStep::HandOver : PairStep::Elsewhere;
            const WallData& wall = walls[segments[p.end2].wall];
            e.x2 = wall.center;
            v2c = wall.vel + spinCross(wall.spin, g.point - wall.center);
            spin2 = wall.spin;
            // The spin part of the shear rate at the half step, as for two balls (above): the
            // lever arm to the contact point shrinks by du_n / 2 over the step, and the arm at
            // the new overlap alone lets a contact that breathes under load while the ball rocks
            // pump energy through its shear spring (a bonded ball in a V: stress seed 2266,
            // -2.7% of its input). The mean arm adds (du_n / 4) (w1 + w2) / dt.
            shear_mid = -0.25 * (vel[s1] - v2c).dot(g.normal) * dt * (spin[s1] + spin2);
            if (!p.active && g.overlap <= -p.activity) return PairStep::Apart;
        }
        const Vec2 v1c = vel[s1] + spinCross(spin[s1], g.point - x1);
        const Vec2 vrel = v2c - v1c;
        e.vrel = vrel;
        // The block's FdBlocks start as copies of the template (below): only what changes from
        // contact to contact is written here, as when one FdBlock served every contact.
        fd.flags = fd_template.flags;
        fd.status = 0;
        fd.tdel = dt;
        fd.time = fd_template.time;
        fd.u_n = g.overlap;
        fd.u_dot_n = -vrel.dot(g.normal);
        fd.u_dot_s = vrel.dot(perp(g.normal)) + shear_mid;
        fd.t_dot_rel = spin2 - spin[s1];
        fd.du_n = fd.u_dot_n * dt;
        fd.du_s = fd.u_dot_s * dt;
        fd.dtheta = fd.t_dot_rel * dt;
        fd.mass_eff = p.mass_eff;
        fd.inv_mass_eff_s = p.inv_mass_eff_s;
        fd.n_force = p.n_force;
        fd.s_force = p.s_force;
        fd.moment = p.moment;
        fd.knest = fd.ksest = fd.krest = 0.0;
        if constexpr (kEnergy)
            for (double& en : fd.energy) en = 0.0;
        return p.active ? PairStep::Contact : PairStep::Touch;
    };

    // ---- pass 3 for a pair that is not a contact this step (Apart or Elsewhere)
    auto finishApart = [&](std::size_t i, const BlockEntry& e, PairStep step)
        __attribute__((always_inline)) {
        const Pair& p = pairs[i];
        const uint32_t s1 = p.end1;
        if (!p.wall) {
            const uint32_t s2 = p.end2;
            if constexpr (kAuto) {
                const Vec2 d = pos[s2] - pos[s1];
                const double dist = d.norm();
                const Vec2 arel = (force[s2] + b.fapp[s2]) * b.inv_mass[s2] -
                                  (force[s1] + b.fapp[s1]) * b.inv_mass[s1];
                noteApproach(p, cold[i], dist - (radius[s1] + radius[s2]), vel[s2] - vel[s1],
                             arel.norm(), dist > 0.0 ? Vec2(d / dist) : Vec2(0.0, 1.0));
            }
            if ((ball_moved[s1] | ball_moved[s2]) && !b.fat[s1].overlaps(b.fat[s2]))
                to_remove.push_back(static_cast<uint32_t>(i));
            return;
        }
        const Segment& sg = segments[p.end2];
        if constexpr (kAuto) {
            if (step == PairStep::Apart) {
                const WallData& wall = walls[sg.wall];
                const Vec2 v2c = wall.vel + spinCross(wall.spin, e.g.point - wall.center);
                const Vec2 a1 = (force[s1] + b.fapp[s1]) * b.inv_mass[s1] + m_gravity;
                noteApproach(p, cold[i], -e.g.overlap, v2c - vel[s1], a1.norm(), e.g.normal);
            }
        }
        if ((ball_moved[s1] | segment_moved[p.end2]) && !b.fat[s1].overlaps(sg.fat))
            to_remove.push_back(static_cast<uint32_t>(i));
    };

    // ---- pass 3 for a contact: its law has run on `fd`
    // (Inlined into both callers: through the closure, every array above costs a load.)
    auto finishContact = [&](std::size_t i, const BlockEntry& e, FdBlock& fd, bool first)
        __attribute__((always_inline)) {
        Pair& p = pairs[i];
        const ContactGeometry& g = e.g;
        const uint32_t s1 = p.end1;
        const Vec2 x1 = pos[s1];
        const double r1 = radius[s1];
        if (fd.status != 0) reportFailedLaw(p, fd);
        if (first && cold[i].born_overlapped) notePlacement(p, cold[i], g.overlap, fd, kEnergy);
        // Non-finite output: summed here, checked once after the loop (findNonFiniteContact).
        finite_check += fd.n_force + fd.s_force + fd.moment + fd.knest + fd.ksest;
        const double fn_old = p.n_force, fs_old = p.s_force, m_old = p.moment;

        // ---- forces onto the ends
        const Vec2 r1c = g.point - x1;
        const Vec2 f = fd.n_force * g.normal + fd.s_force * perp(g.normal);
        force[s1] -= f;
        moment[s1] -= cross(r1c, f) + fd.moment;
        if (!p.wall) {
            force[p.end2] += f;
            moment[p.end2] += cross(g.point - e.x2, f) + fd.moment;
        } else {
            WallData& w = walls[segments[p.end2].wall];
            w.force += f;
            w.moment += cross(g.point - w.center, f) + fd.moment;
            w.knest += fd.knest;
        }

        // ---- extras
        const bool ends =
            g.overlap <= -p.activity && !(fd.flags & kFdKeep) && p.model->OKToDelete();
        if constexpr (kAuto || kEnergy || kGuard) {
            PairCold& c = cold[i];
            if constexpr (kAuto) {
                c.krest = fd.krest;
                noteContact(p, c, fd.knest, fd.ksest, fd.krest, r1c.squaredNorm(),
                            p.wall ? 0.0 : (g.point - e.x2).squaredNorm(), p.mass_eff);
            }
            if constexpr (kEnergy) {
                // The plugin's partitions against the ABI's contract (rare path when broken).
                // Only with finite kinematics: a state already non-finite is the engine's
                // to report (findNonFiniteContact, the law of motion), not the plugin's fault.
                if (std::isfinite(fd.u_n + fd.du_n + fd.du_s + fd.dtheta) &&
                    (!std::isfinite(fd.energy[0] + fd.energy[1] + fd.energy[2] + fd.energy[3] +
                                    fd.energy[4] + fd.energy[5]) ||
                     fd.energy[kEnergySlip] < 0.0 || fd.energy[kEnergyDashpot] < 0.0 ||
                     fd.energy[kEnergyPlastic] < 0.0)) {
                    checkEnergyContract(p, c, fd, fn_old, fs_old, m_old);
                }
                m_books.acc.slip += fd.energy[kEnergySlip];
                // The dashpot impulse spans the velocity window around this step: booked at
                // the next energy snapshot, half before it (law_of_motion.cpp).
                m_books.dashpot_pending += fd.energy[kEnergyDashpot];
                m_books.acc.plastic += fd.energy[kEnergyPlastic];
                // A break releases what the bond held (accuracy-reference 3.6, pitfall 2; the
                // model says how much), and so does the end of a contact that is still loaded.
                m_books.acc.released += fd.energy[kEnergyReleased];
                c.strain = fd.energy[kEnergyStrain];
                c.bond = fd.energy[kEnergyBondStrain];
                double held = 0.0;
                if (m_books.strain_baseline_pending && !first) {
                    held = storedBefore(fd, fn_old, fs_old, m_old);
                    held_before += held;
                }
                if (ends) {
                    m_books.acc.released += c.strain + c.bond;
                } else {
                    strain_now += c.strain;
                    bond_now += c.bond;
                }
                // Group shares and the work across group borders (group_energy.cpp): one
                // branch per contact, taken only with groups traced.
                if (groups) bookContactToGroups(i, fd, first, ends, held, f, g.point);
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
                if (!growing && p.loading) noteDeepest(p, cold[i], fn_old, fd.u_dot_n);
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
        if (fd.flags & kFdBroken) queueBreak(i, g.point, fd);
        if (ends) {
            endContact(p, cold[i], kGuard);
            // Its ends may have moved apart while it was a contact (inactive pairs are checked
            // only when an end is re-inserted).
            const Box& fat2 = p.wall ? segments[p.end2].fat : b.fat[p.end2];
            if (!b.fat[s1].overlaps(fat2)) to_remove.push_back(static_cast<uint32_t>(i));
        }
    };

    ForceScratch& scratch = m_contacts->force_scratch;
    const std::size_t npairs = pairs.size();
    const int nthreads = forceThreads(npairs);
    prepareForceScratch(nthreads, fd_template);
    // In the threads' pipeline the consumer pauses the producers around what may move the
    // pairs in memory (a new pair for a wall contact's hand-over, when the vector is full).
    PaddedCounter pause, busy;  // pause: 1 while held; busy: producers inside a production
    auto holdProducers = [&](bool hold) {
        if (nthreads <= 1) return;
        pause.value.store(hold ? 1 : 0, std::memory_order_seq_cst);
        if (hold)
            while (busy.value.load(std::memory_order_seq_cst) != 0) std::this_thread::yield();
    };

    // The contact objects live apart from the pairs, which only point to them: ask for the
    // first three cache lines of the object a few pairs ahead of pair i (the shipped models'
    // objects are 88 to 184 bytes).
    auto prefetchModel = [&](std::size_t i, std::size_t end) __attribute__((always_inline)) {
        if (i + kPrefetchAhead >= end) return;
        const Pair& ahead = pairs[i + kPrefetchAhead];
        if (!ahead.active) return;
        const char* obj = reinterpret_cast<const char*>(ahead.model);
        __builtin_prefetch(obj);
        __builtin_prefetch(obj + 64);
        __builtin_prefetch(obj + 128);
    };

    // ---- pass 1 and 2 for the pairs from `i` to at most `end` into `blk`: stops before a rare
    // pair (blk.stop names it) or, for the threads' producers (`serial_walls`), before any wall
    // pair, which only the consumer may process (below). No side effect outside `blk` and the
    // contacts' own model objects.
    auto produce = [&](std::size_t i, std::size_t end, ForceBlock & blk, bool serial_walls)
        __attribute__((always_inline)) {
        std::size_t n = 0, ncontacts = 0;
        blk.stop = PairStep::Contact;
        blk.batched = 0;
        for (; i < end && n < kBlock; ++i) {
            // (a producer reads no wall pair: the consumer may be swapping their state)
            if (!(serial_walls && i + kPrefetchAhead < end && scratch.wall[i + kPrefetchAhead]))
                prefetchModel(i, end);
            if (serial_walls && scratch.wall[i]) {
                blk.stop = PairStep::Wall;  // the consumer takes over here
                break;
            }
            BlockEntry& e = blk.entries[n];
            const PairStep step = geometry(i, e, blk.fd[ncontacts]);
            if (step == PairStep::Touch || step == PairStep::HandOver) {
                blk.stop = step;
                break;
            }
            e.pair = static_cast<uint32_t>(i);
            e.step = step;
            if (step == PairStep::Contact) {
                const Pair& p = pairs[i];
                blk.models[ncontacts] = p.model;
                blk.laws[ncontacts] = batched ? p.rule->factory->batch : nullptr;
                e.block = static_cast<uint32_t>(ncontacts++);
            }
            ++n;
        }
        blk.n = n;
        blk.ncontacts = ncontacts;
        blk.next = i;
        // pass 2: runs of contacts of one batched law in one call each, the rest one by one
        for (std::size_t k = 0; k < ncontacts;) {
            std::size_t last = k + 1;
            if (blk.laws[k]) {
                while (last < ncontacts && blk.laws[last] == blk.laws[k]) ++last;
                blk.laws[k](blk.models + k, blk.fd + k, static_cast<int32_t>(last - k));
                blk.batched += static_cast<int64_t>(last - k);
            } else {
                callLaw(blk.models[k], blk.fd[k], blk.error);
            }
            k = last;
        }
    };

    // ---- pass 3 of a block, in pair order
    auto consume = [&](ForceBlock & blk) __attribute__((always_inline)) {
        m_profile.batched_laws += blk.batched;
        for (std::size_t k = 0; k < blk.n; ++k) {
            const BlockEntry& e = blk.entries[k];
            if (e.step == PairStep::Contact)
                finishContact(e.pair, e, blk.fd[e.block], false);
            else
                finishApart(e.pair, e, e.step);
        }
    };

    // ---- the rare pair that stopped `blk` (blk.next), alone; returns the next pair to process.
    // Pass 1 left its geometry in entries[n] and its FdBlock in fd[ncontacts], which passes 2
    // and 3 did not touch.
    auto processRare = [&](std::size_t i, PairStep stop, BlockEntry& e, FdBlock& fd,
                           std::string& error) -> std::size_t {
        if (stop == PairStep::HandOver) {
            // The contact crossed a convex vertex and moves, state and all, to the holder's
            // pair, which now sits in slot i: process slot i again (a pair may have been
            // created).
            const bool full = pairs.size() == pairs.capacity();
            if (full) holdProducers(true);
            const bool moved = handOverWallContact(i);
            if (full) holdProducers(false);
            if (moved) return i;
            // No pair can take it (no holder, or one with a contact of its own): the contact
            // ends here, and what it still stores is released.
            Pair& p = pairs[i];
            if constexpr (kEnergy) {
                m_books.acc.released += cold[i].strain + cold[i].bond;
                if (groups) bookReleasedToGroups(p, cold[i].strain + cold[i].bond);
            }
            endContact(p, cold[i], kGuard);
            finishApart(i, e, PairStep::Elsewhere);
            return i + 1;
        }
        // A pair touching for the first time: activate it, then its law (FDlaw, and the first
        // call's flags), then its finish.
        Pair& p = pairs[i];
        const bool first = activate(p, cold[i], e.g, e.vrel);
        if (first) {
            fd.flags |= kFdFirstCall | m_activation_flags;
        } else {
            // A wall pair that took over its chain's contact from a neighbouring segment's pair
            // (activate, adoptWallContact): the forces are that contact's.
            fd.n_force = p.n_force;
            fd.s_force = p.s_force;
            fd.moment = p.moment;
        }
        callLaw(p.model, fd, error);
        finishContact(i, e, fd, first);
        return i + 1;
    };

    // ---- one thread: pair after pair, all three passes at once. Measured: on one thread the
    // blocks cost more (each contact's FdBlock and geometry go through memory between the
    // passes) than one batched call per block saves, so here the batched law runs per contact
    // (count 1: no virtual call, the same bits) and the blocks serve the threads' pipeline.
    auto serialRange = [&](std::size_t i, std::size_t end, ForceBlock& blk) {
        BlockEntry e;
        FdBlock fd = blk.fd[0];
        int64_t batched_count = 0;
        while (i < end) {
            prefetchModel(i, end);
            const PairStep step = geometry(i, e, fd);
            if (step == PairStep::Contact) {
                Pair& p = pairs[i];
                const BatchFdLawFn batch = batched ? p.rule->factory->batch : nullptr;
                if (batch) {
                    ContactModel* model = p.model;
                    batch(&model, &fd, 1);
                    ++batched_count;
                } else {
                    callLaw(p.model, fd, blk.error);
                }
                finishContact(i, e, fd, false);
                ++i;
            } else if (step == PairStep::Apart || step == PairStep::Elsewhere) {
                finishApart(i, e, step);
                ++i;
            } else {
                i = processRare(i, step, e, fd, blk.error);
            }
        }
        m_profile.batched_laws += batched_count;
    };

    if (nthreads <= 1) {
        serialRange(0, npairs, *scratch.ring[0]);
    } else {
#ifdef TALUS_HAVE_OPENMP
        // Threads (docs/architecture.md, "Threads"): a pipeline over the fixed blocks of kBlock
        // pairs. Producers (every thread, the consumer too while it waits) claim blocks in order
        // and run passes 1 and 2 into a ring of ForceBlocks; thread 0, the consumer, runs pass 3
        // of block after block in pair order, and the rest of a block that stopped (a rare pair
        // or a wall pair) serially, as one thread would. A block's production reads only the
        // positions and velocities, its own pairs and their model objects, which nothing else
        // touches until the consumer reaches it; so every result is the one-thread result, bit
        // for bit, for any thread count. Wall pairs are the consumer's alone because a rare
        // wall pair may swap another wall pair's state (adoptWallContact, handOverWallContact).
        ++m_profile.threaded_steps;
        const std::size_t nblocks = (npairs + kBlock - 1) / kBlock;
        const std::size_t ring = scratch.ring.size();
        PaddedCounter claim;     // the next block to produce
        PaddedCounter consumed;  // blocks whose pass 3 is done
        std::atomic<bool> finished{false};
        for (std::size_t k = 0; k < ring; ++k)
            scratch.ready[k].value.store(0, std::memory_order_relaxed);
        // Room for the pairs a hand-over may add, so that the producers' pairs do not move
        // (holdProducers covers the case that it is not enough).
        pairs.reserve(npairs + npairs / 8 + 64);
        cold.reserve(npairs + npairs / 8 + 64);
        // Claims block `claim` if it exists and the ring has room for it (plain loads first:
        // a waiting thread polls this). The busy count around the production lets the consumer
        // wait for the producers to be out before it moves the pairs (holdProducers).
        auto tryProduce = [&]() -> bool {
            std::size_t k = claim.value.load(std::memory_order_relaxed);
            if (k >= nblocks || k >= consumed.value.load(std::memory_order_acquire) + ring ||
                pause.value.load(std::memory_order_seq_cst) != 0)
                return false;
            busy.value.fetch_add(1, std::memory_order_seq_cst);
            bool done = false;
            if (pause.value.load(std::memory_order_seq_cst) == 0 &&
                claim.value.compare_exchange_strong(k, k + 1, std::memory_order_acq_rel)) {
                const std::size_t first = k * kBlock;
                produce(first, std::min(first + kBlock, npairs), *scratch.ring[k % ring], true);
                scratch.ready[k % ring].value.store(k + 1, std::memory_order_release);
                done = true;
            }
            busy.value.fetch_sub(1, std::memory_order_seq_cst);
            return done;
        };
        auto wait = [](int& spins) {
            if (++spins < kSpinsBeforeYield) {
                spinPause();
            } else {
                spins = 0;
                std::this_thread::yield();
            }
        };
        std::exception_ptr failure;
#pragma omp parallel num_threads(nthreads)
        {
            if (omp_get_thread_num() == 0) {
                try {
                    for (std::size_t k = 0; k < nblocks; ++k) {
                        ForceBlock& blk = *scratch.ring[k % ring];
                        int spins = 0;
                        while (scratch.ready[k % ring].value.load(std::memory_order_acquire) !=
                               k + 1)
                            if (!tryProduce()) wait(spins);
                        consume(blk);
                        if (blk.stop != PairStep::Contact) {
                            // The block's rest, serially: the stop (a rare pair or a wall pair)
                            // and the pairs after it up to the block's end.
                            serialRange(blk.next, std::min((k + 1) * kBlock, npairs),
                                        *scratch.remainder);
                        }
                        consumed.value.store(k + 1, std::memory_order_release);
                    }
                } catch (...) {
                    failure = std::current_exception();
                }
                finished.store(true, std::memory_order_release);
            } else {
                int spins = 0;
                while (!finished.load(std::memory_order_acquire) &&
                       claim.value.load(std::memory_order_relaxed) < nblocks)
                    if (!tryProduce()) wait(spins);
            }
        }
        if (failure) std::rethrow_exception(failure);
#else
        serialRange(0, npairs, *scratch.ring[0]);
#endif
    }

    if (!std::isfinite(finite_check)) findNonFiniteContact();
    for (auto it = to_remove.rbegin(); it != to_remove.rend(); ++it) removePair(*it);
    clearMovedFlags();
    if constexpr (kEnergy) {
        m_books.acc.strain = strain_now;
        m_books.acc.bond = bond_now;
        if (groups) groupForceLoopEnd();
        if (m_books.strain_baseline_pending) {
            // Tracing was switched on with loaded contacts: what they hold was put in before
            // the books opened (bookkeeping.cpp, setEnergyTracing).
            m_books.acc.initial_strain = held_before;
            m_books.strain_baseline_pending = false;
        }
    }
}

// ------------------------------------------------------------------------ threads

void Model::setThreads(int n, int grain) {
    if (n < 1 || n > 1024)
        throw InputError("threads: the thread count must be from 1 to 1024 (got " +
                         std::to_string(n) + ")");
    if (grain < 1)
        throw InputError("threads: the grain (fewest pairs per thread) must be >= 1 (got " +
                         std::to_string(grain) + ")");
    m_threads = n;
    m_thread_grain = grain;
}

int Model::threads() const {
    if (m_threads > 0) return m_threads;
    // TALUS_THREADS (talus run --threads N sets it): a bad value is the CLI's to refuse; here
    // it falls back to one thread.
    const char* env = std::getenv("TALUS_THREADS");
    if (!env || !*env) return 1;
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    return (*end == '\0' && n >= 1 && n <= 1024) ? static_cast<int>(n) : 1;
}

int Model::threadGrain() const {
    if (m_thread_grain > 0) return m_thread_grain;
    // TALUS_THREAD_GRAIN: for tests that run small scenes on threads (stress suite).
    const char* env = std::getenv("TALUS_THREAD_GRAIN");
    if (!env || !*env) return kDefaultThreadGrain;
    char* end = nullptr;
    const long g = std::strtol(env, &end, 10);
    return (*end == '\0' && g >= 1 && g <= 1000000000) ? static_cast<int>(g) : kDefaultThreadGrain;
}

bool Model::threadingAvailable() {
#ifdef TALUS_HAVE_OPENMP
    return true;
#else
    return false;
#endif
}

int Model::forceThreads(std::size_t npairs) const {
#ifdef TALUS_HAVE_OPENMP
    const int wanted = threads();
    if (wanted <= 1) return 1;
    const std::size_t by_grain = npairs / static_cast<std::size_t>(threadGrain());
    const int n =
        static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(wanted), by_grain));
    if (n < 2) return 1;
    for (const auto& rule : m_contacts->rules)
        if (rule->prototype && !(rule->prototype->Traits() & kTraitThreadSafe)) return 1;
    return n;
#else
    (void)npairs;
    return 1;
#endif
}

void Model::prepareForceScratch(int nthreads, const FdBlock& tmpl) {
    ForceScratch& s = m_contacts->force_scratch;
    // Four blocks per thread in the ring: a producer that finished its block can take the next
    // while the consumer is still one or two behind. A new block's FdBlocks start as copies of
    // the template; pass 1 writes every field that changes from step to step or contact to
    // contact, so they are not refilled.
    auto fresh = [&] {
        auto blk = std::make_unique<ForceBlock>();
        std::fill(blk->fd, blk->fd + kBlock, tmpl);
        return blk;
    };
    const std::size_t ring = nthreads <= 1 ? 1 : 4 * static_cast<std::size_t>(nthreads);
    while (s.ring.size() < ring) s.ring.push_back(fresh());
    if (nthreads <= 1) return;
    if (!s.remainder) s.remainder = fresh();
    if (s.ready.size() < s.ring.size()) s.ready = std::vector<PaddedCounter>(s.ring.size());
    const auto& pairs = m_contacts->pairs;
    s.wall.resize(pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) s.wall[i] = pairs[i].wall;
}

// The rare paths of the loop, kept out of it so that its body stays small.

bool Model::activate(Pair& p, PairCold& c, const ContactGeometry& g, const Vec2& vrel) {
    // A wall pair may be taking over the ball's contact from a neighbouring segment's pair
    // (a convex vertex crossed, that pair later in the loop): then the contact goes on.
    if (p.wall && adoptWallContact(pairIndex(p))) return false;
    if (c.rules_version != m_contacts->rules_version) refreshRule(p);
    // A pair whose bond broke or was removed is not bonded again by a rule (model_bonds.cpp);
    // the lookup runs only in a model where that happened.
    m_activation_flags = m_contacts->unbonded.empty() ? 0u : autoBondFlags(p, c);
    p.active = true;
    ++m_profile.contacts_created;
    c.duration = p.model->ContactDuration(p.mass_eff, std::max(0.0, -vrel.dot(g.normal)));
    // The resolution rule and the guard divide by it: NaN, zero or negative would silently
    // switch both off (docs/plugin-abi.md, time-step contract). +inf means "no force".
    if (!(c.duration > 0.0))
        throw PluginError("contact model '" + p.rule->model_name + "' at step " +
                          std::to_string(m_step) + " on " + describePair(p) +
                          ": ContactDuration(mass_eff " + num(p.mass_eff) + " kg, approach " +
                          num(std::max(0.0, -vrel.dot(g.normal))) + " m/s) returned " +
                          num(c.duration) + " s (must be > 0, +inf for no force)");
    // A rule whose contacts have no stiffness at all (m:contact_model("linear") with no kn:
    // the bodies pass through each other) is worth one warning per rule: no tangent stiffness
    // at touch and no finite duration even at 1 m/s means the model exerts no normal force.
    if (!p.rule->warned_no_stiffness && !(p.model->KnEstimate() > 0.0) &&
        !(p.model->ContactDuration(p.mass_eff, 1.0) < HUGE_VAL)) {
        p.rule->warned_no_stiffness = true;
        std::string zero;
        for (int32_t k = 0; k < p.model->PropCount(); ++k) {
            const PropInfo* info = p.model->PropInfoAt(k);
            if (!info || (info->flags & (kPropReadOnly | kPropState))) continue;
            const std::string units = info->units ? info->units : "";
            // zero, or subnormal (1e-320 Pa: a stiffness that ends up zero in every product)
            const double v = p.model->ReturnProp(k);
            if ((units == "N/m" || units == "Pa") && std::fabs(v) < DBL_MIN)
                zero += std::string(zero.empty() ? "" : ", ") + info->name + " = " + num(v);
        }
        // Only a model with a stiffness property at 0 is warned about: a model made to exert no
        // force (the template's `null`) has none.
        if (!zero.empty())
            warn("contact model '" + p.rule->model_name + "' has no normal stiffness on " +
                 describePair(p) + " (" + zero + ")" +
                 ": the bodies will pass through each other; set the stiffness in "
                 "m:contact_model{...} or on the bodies (warned once per contact_model rule)");
    }
    // For the guard: a contact born overlapping (placed so) gives back energy it never took.
    // How much of the overlap the last step's motion made. Positions at the previous step are
    // x - v dt exactly (the half-step velocity moved them), so for two balls the overlap then
    // is known exactly; for a wall, the normal closing plus the turn of the line from the
    // vertex or the face, (v_t dt)^2 / (2 r). (The contact-point velocity would add the spins,
    // which turn the balls but do not close the gap.) More overlap than that was there before.
    const auto& b = m_bodies->balls;
    const double approach = -vrel.dot(g.normal);
    c.approach_rate = std::max(approach, 0.0);
    if (!p.wall) {
        const Vec2 d = b.pos[p.end2] - b.pos[p.end1];
        const Vec2 step = (b.vel[p.end2] - b.vel[p.end1]) * m_dt;
        const double rsum = b.radius[p.end1] + b.radius[p.end2];
        c.closure = std::max(g.overlap - (rsum - (d - step).norm()), 0.0);
    } else {
        const WallData& w = m_bodies->walls[m_bodies->segments[p.end2].wall];
        const Vec2 step = (w.vel + spinCross(w.spin, g.point - w.center) - b.vel[p.end1]) * m_dt;
        const double slide = step.dot(perp(g.normal));
        c.closure = std::max(-step.dot(g.normal), 0.0) + slide * slide / (2.0 * b.radius[p.end1]);
    }
    c.born_overlapped = g.overlap > c.closure * (1.0 + 1e-9) + 1e-15;
    if (m_contact_events) {
        Event ev;
        ev.kind = EventKind::ContactCreated;
        ev.time = m_time;
        ev.pos = g.point;
        ev.contact = ContactKey{c.key};
        ev.model = p.rule->model_name;
        m_events.push_back(std::move(ev));
    }
    return true;
}

void Model::checkEnergyContract(const Pair& p, const PairCold& c, const FdBlock& fd, double fn_old,
                                double fs_old, double m_old) {
    const double scale = std::fabs(c.strain) + std::fabs(c.bond) +
                         std::fabs(fd.energy[kEnergyStrain]) +
                         std::fabs(fd.energy[kEnergyBondStrain]) +
                         (std::fabs(fn_old) + std::fabs(fd.n_force)) * std::fabs(fd.du_n) +
                         (std::fabs(fs_old) + std::fabs(fd.s_force)) * std::fabs(fd.du_s) +
                         (std::fabs(m_old) + std::fabs(fd.moment)) * std::fabs(fd.dtheta);
    const double totals[kEnergyCount] = {
        0.0, m_books.acc.slip, m_books.acc.dashpot, m_books.acc.plastic, 0.0, 0.0};
    const std::string why = energyContractViolation(fd, scale, totals);
    if (!why.empty()) {
        const std::string what = "contact model '" + p.rule->model_name + "' at step " +
                                 std::to_string(m_step) + " on " + describePair(p) + ": " + why;
        // NaN stops the run. A negative total warns once per rule: contacts
        // born overlapping and the half-step settling at separation make it
        // happen in sound runs (docs/plugin-abi.md, "Energies").
        if (why.compare(0, 9, "negative ") != 0) throw PluginError(what);
        if (!p.rule->warned_negative_dissipation) {
            p.rule->warned_negative_dissipation = true;
            warn(what + " (warned once per contact_model rule)");
        }
    }
}

void Model::notePlacement(const Pair& p, const PairCold& c, double overlap, const FdBlock& fd,
                          bool energy) {
    // The model's stored energy at its first call includes what the closure within this step
    // put in (activate); the rest was there before the step. Stored energy grows about as the
    // overlap squared (exactly so for a linear spring), so the part that was placed is the fraction
    // ((overlap - approach dt) / overlap)^2 of it. Without tracing, the linear estimate
    // knest overlap^2 / 2 names the size in the warning.
    const double before = std::max(overlap - c.closure, 0.0);
    const double share = overlap > 0.0 ? (before / overlap) * (before / overlap) : 0.0;
    const double stored = energy ? fd.energy[kEnergyStrain] + fd.energy[kEnergyBondStrain]
                                 : 0.5 * fd.knest * overlap * overlap;
    const double placed = share * stored;
    if (energy) m_books.acc.placement += placed;
    m_books.last_placed = placed;
    // Below a thousandth of the radius it is bookkeeping, not a user's placement (a contact
    // formed by a spin-driven slide, rounding). Booked, not reported.
    const auto& b = m_bodies->balls;
    const double r = p.wall ? b.radius[p.end1] : std::min(b.radius[p.end1], b.radius[p.end2]);
    if (overlap < 1e-3 * r) return;
    m_guard_state.placed_energy += placed;
    if (m_guard_state.placed++ == 0) {
        m_guard_state.placed_first =
            describePair(p) + " at step " + std::to_string(m_step) + ": overlap " + num(overlap) +
            " m (" + num(100.0 * overlap / r) + "% of the smaller radius), stored energy " +
            num(placed) + " J" + (energy ? "" : " (estimated from knest)");
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

void Model::queueBreak(std::size_t i, const Vec2& point, const FdBlock& fd) {
    forgetBond(i);
    Event ev;
    ev.kind = EventKind::BondBreak;
    ev.time = m_time;
    ev.pos = point;
    ev.contact = ContactKey{m_contacts->cold[i].key};
    ev.mode = fd.break_mode;
    ev.model = m_contacts->pairs[i].rule->model_name;
    if (fd.flags & kFdBreakStress) {
        ev.sigma = fd.reserved[0];
        ev.tau = fd.reserved[1];
    }
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
    for (const Pair& p : m_contacts->pairs)
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
            if (m_guard_state.energy_gain++ == 0) m_guard_state.energy_gain_first = what;
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
            if (m_guard_state.underresolved++ == 0) m_guard_state.underresolved_first = what;
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
            if (m_guard_state.stiffness_lies++ == 0) m_guard_state.stiffness_lies_first = what;
        }
    }
    resetPair(p);
}

}  // namespace talus
