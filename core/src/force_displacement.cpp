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
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <type_traits>

#include "body_store.hpp"
#include "contact_store.hpp"
#include "engine.hpp"
#include "model_internal.hpp"
#include "narrowphase.hpp"
#include "step_limits.hpp"
#include "talus/errors.hpp"
#include "talus/sdk/dashpot.hpp"

#ifdef TALUS_HAVE_OPENMP
#include <omp.h>
#endif

namespace talus {

namespace {

constexpr std::size_t kPrefetchAhead = 4;

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
template <class Fd>  // FdBlock, or a lane contact's LaneResult
double storedBefore(const Fd& fd, double fn_old, double fs_old, double m_old) {
    const double work = 0.5 * ((fn_old + fd.n_force) * fd.du_n - (fs_old + fd.s_force) * fd.du_s -
                               (m_old + fd.moment) * fd.dtheta);
    return fd.energy[kEnergyStrain] + fd.energy[kEnergyBondStrain] + fd.energy[kEnergySlip] +
           fd.energy[kEnergyDashpot] + fd.energy[kEnergyPlastic] + fd.energy[kEnergyReleased] -
           work;
}

std::string num(double v) { return messageNumber(v); }

/// A law's output as an FdBlock (the energy contract's rare path takes one).
const FdBlock& asFdBlock(const FdBlock& fd, const FdBlock&) { return fd; }
FdBlock asFdBlock(const LaneResult& r, const FdBlock& tmpl) { return r.block(tmpl); }

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

template <bool kAuto, bool kEnergy, bool kGuard>
void forceLoop(World& world);

}  // namespace

void forceDisplacement(World& world) {
    const bool automatic = world.settings.timestep.automatic;
    const bool guard = world.settings.guard.energy != GuardAction::Off ||
                       world.settings.guard.resolution != GuardAction::Off ||
                       world.settings.guard.stiffness != GuardAction::Off;
    // Dispatch once per step to the loop compiled for exactly what this scene needs.
    if (automatic) {
        if (world.books.on)
            guard ? forceLoop<true, true, true>(world) : forceLoop<true, true, false>(world);
        else
            guard ? forceLoop<true, false, true>(world) : forceLoop<true, false, false>(world);
    } else {
        if (world.books.on)
            guard ? forceLoop<false, true, true>(world) : forceLoop<false, true, false>(world);
        else
            guard ? forceLoop<false, false, true>(world) : forceLoop<false, false, false>(world);
    }
}

// Every pair goes through three passes:
//   1. geometry: the pair's narrowphase and, for a contact, its FdBlock (no side effects);
//   2. the law: the model's batched FDlaw (one contact per call: no virtual call), or FDlaw;
//   3. finish: forces onto the ends, the time-step notes, the books, the guard.
// One thread runs them pair after pair, adding each contact onto its ends at once.
//
// Threads (docs/architecture.md, "Threads") own contiguous ranges of pairs and run all three
// passes on them, with what reaches beyond the pair kept aside: each pair's action on its ends
// goes into its PairAction, and whatever allocates or frees model objects, raises an event or
// touches another pair (activation, a wall pair, a break, the end of a contact, a pair to remove)
// into the thread's list of deferred work, in pair order. Then one thread does the deferred work
// of all threads in pair order, and the balls gather their pairs' actions in pair order
// (gatherPairActions). Every sum is thus made of the same terms in the same order as on one
// thread, the time-step limits take the lowest pair on a tie, and the result is the same bit
// for bit for any thread count (lua.regress.force_loop_identical).
namespace {

template <bool kAuto, bool kEnergy, bool kGuard>
void forceLoop(World& world) {
    // References to the stores' arrays, taken once: the loop body reads them as it read the
    // members they were before the stores existed (no extra load per pair).
    auto& b = world.bodies.balls;
    auto& walls = world.bodies.walls;
    const auto& segments = world.bodies.segments;
    auto& pairs = world.contacts.pairs;
    auto& cold = world.contacts.cold;
    const auto& ball_moved = world.contacts.ball_moved;
    const auto& segment_moved = world.contacts.segment_moved;
    auto& to_remove = world.contacts.to_remove;
    ForceScratch& scratch = world.contacts.force_scratch;
    const std::size_t npairs = pairs.size();
    const int nthreads = forceThreads(world, npairs);
    world.clock.threads = nthreads;
    if (nthreads <= 1) {
        std::fill(b.force.begin(), b.force.end(), Vec2::Zero());
        std::fill(b.moment.begin(), b.moment.end(), 0.0);
    }  // (threads: the gather writes every ball)
    for (auto& w : walls) w.force.setZero(), w.moment = 0.0, w.knest = 0.0;
    if constexpr (kAuto) {
        if (nthreads <= 1) {
            std::fill(b.k_tran.begin(), b.k_tran.end(), 0.0);
            std::fill(b.k_rot.begin(), b.k_rot.end(), 0.0);
        }
        world.stepping.limits = StepLimits{};
        world.stepping.limits_stale = false;
        scratch.apart.clear();
    }
    const double dt = world.clock.dt;
    FdBlock fd_template = world.contacts.fd_template;
    fd_template.tdel = dt;
    fd_template.time = world.clock.time;
    fd_template.flags = kEnergy ? kFdEnergyOn : 0u;
    double strain_now = 0.0, bond_now = 0.0;
    double held_before = 0.0;  // stored by contacts older than the tracing (baseline, once)
    double finite_check = 0.0;
    to_remove.clear();
    const bool groups = kEnergy && world.books.groups.on;
    if (groups) groupForceLoopStart(world);
    // The dissipation totals before this step, for the energy contract's check (the same for
    // every contact, so for every thread count).
    const EnergyTotals totals_before = world.books.acc;
    const Vec2* pos = b.pos.data();
    const Vec2* vel = b.vel.data();
    const double* radius = b.radius.data();
    const double* spin = b.spin.data();
    Vec2* force = b.force.data();
    double* moment = b.moment.data();
    const bool batched = world.settings.batched_law;
    // Lanes (docs/plugin-abi.md, "Lanes") are part of the batched path; per-group energy books
    // every contact through its FdBlock (bookContactToGroups), so it runs without them.
    bool lanes_on = false;
    if (world.settings.lanes && batched && !groups)
        for (const auto& rule : world.contacts.rules)
            lanes_on = lanes_on || (rule->factory && rule->factory->lanes);
    // A step without them takes every contact out first (their objects run FDlaw).
    if (!lanes_on)
        for (const auto& rule : world.contacts.rules)
            if (rule->lanes && rule->lanes->used() > 0) {
                leaveAllLanes(world);
                break;
            }
    auto laneable = [](const Pair& p) __attribute__((always_inline)) {
        return !p.wall && p.rule->factory && p.rule->factory->lanes;
    };
    if (nthreads > 1) prepareForceScratch(world, nthreads, fd_template);
    PairAction* actions = scratch.actions.data();
    PairStiffness* stiffness = kAuto && nthreads > 1 ? scratch.stiffness.data() : nullptr;
    PairEnergy* energies = kEnergy && nthreads > 1 ? scratch.energies.data() : nullptr;

    // What one contact adds to the books, in the order one thread adds it (PairEnergy).
    auto bookPairEnergy = [&](const PairEnergy& pe) __attribute__((always_inline)) {
        if (pe.what & PairEnergy::kPlacement) world.books.acc.placement += pe.placement;
        if (pe.what & PairEnergy::kContact) {
            world.books.acc.slip += pe.slip;
            // The dashpot impulse spans the velocity window around this step: booked at the
            // next energy snapshot, half before it (law_of_motion.cpp).
            world.books.dashpot_pending += pe.dashpot;
            world.books.acc.plastic += pe.plastic;
            world.books.acc.released += pe.released;
        }
        if (pe.what & PairEnergy::kHeld) held_before += pe.held;
        if (pe.what & (PairEnergy::kEnds | PairEnergy::kHandOver))
            world.books.acc.released += pe.released_end;
        if (pe.what & PairEnergy::kStored) {
            strain_now += pe.strain;
            bond_now += pe.bond;
        }
    };

    // How a finish delivers what reaches beyond its pair (the threads' scheme, above).
    using Direct = std::integral_constant<int, 0>;    // one thread: onto the ends at once
    using Serial = std::integral_constant<int, 1>;    // threads, serial part: actions recorded
    using Parallel = std::integral_constant<int, 2>;  // threads, a range: actions, deferred work

    // ---- a contact's FdBlock from its geometry. Only what changes from contact to contact is
    // written: the rest is the step's template (the thread's copy).
    auto fillFd = [&](const Pair& p, double overlap, double u_dot_n, double u_dot_s,
                      double t_dot_rel, FdBlock& fd) __attribute__((always_inline)) {
        fd.flags = fd_template.flags;
        fd.status = 0;
        fd.tdel = dt;
        fd.time = fd_template.time;
        fd.u_n = overlap;
        fd.u_dot_n = u_dot_n;
        fd.u_dot_s = u_dot_s;
        fd.t_dot_rel = t_dot_rel;
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
    };

    // ---- pass 1: the geometry of pair i into `e` and, for a contact, the law's inputs: into
    // `fd` when given, else into `e` (a lane block's pass 1)
    auto geometry = [&](std::size_t i, PairEntry & e, FdBlock * fd) __attribute__((always_inline))
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
            if (!segmentGeometry(world, p.end2, x1, r1, g))
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
        const double u_dot_n = -vrel.dot(g.normal);
        const double u_dot_s = vrel.dot(perp(g.normal)) + shear_mid;
        const double t_dot_rel = spin2 - spin[s1];
        if (fd) {
            fillFd(p, g.overlap, u_dot_n, u_dot_s, t_dot_rel, *fd);
        } else {
            e.u_dot_n = u_dot_n;
            e.u_dot_s = u_dot_s;
            e.t_dot_rel = t_dot_rel;
        }
        return p.active ? PairStep::Contact : PairStep::Touch;
    };

    // ---- pass 3 for a pair that is not a contact this step (Apart or Elsewhere)
    auto finishApart = [&](auto mode, std::size_t i, PairStep step, ForceThreadPart* part)
        __attribute__((always_inline)) {
        constexpr int kMode = decltype(mode)::value;
        const Pair& p = pairs[i];
        if constexpr (kMode != Direct::value) {
            std::fill(&actions[i].add[0][0], &actions[i].add[0][0] + 6, -0.0);
            if constexpr (kAuto)
                std::fill(&stiffness[i].add[0][0], &stiffness[i].add[0][0] + 4, -0.0);
            if constexpr (kEnergy) energies[i].what = 0;
        }
        // The approach limit needs the step's complete forces: noted after the loop.
        if constexpr (kAuto) {
            if (step == PairStep::Apart)
                (kMode == Parallel::value ? part->apart : scratch.apart)
                    .push_back(static_cast<uint32_t>(i));
        }
        const uint32_t s1 = p.end1;
        const bool moved = p.wall ? (ball_moved[s1] | segment_moved[p.end2]) != 0
                                  : (ball_moved[s1] | ball_moved[p.end2]) != 0;
        if (moved && !b.fat[s1].overlaps(p.wall ? segments[p.end2].fat : b.fat[p.end2])) {
            if constexpr (kMode == Parallel::value)
                part->items.push_back({static_cast<uint32_t>(i), Deferred::Remove});
            else
                to_remove.push_back(static_cast<uint32_t>(i));
        }
    };

    // A contact that ended (ends), after the rest of its finish: a fresh model object for its
    // next touch, and the broadphase check its ends may need.
    auto endAndCheck = [&](std::size_t i) {
        Pair& p = pairs[i];
        endContact(world, p, cold[i], kGuard);
        // Its ends may have moved apart while it was a contact (inactive pairs are checked
        // only when an end is re-inserted).
        const Box& fat2 = p.wall ? segments[p.end2].fat : b.fat[p.end2];
        if (!b.fat[p.end1].overlaps(fat2)) to_remove.push_back(static_cast<uint32_t>(i));
    };

    // ---- pass 3 for a contact: its law has run on `fd`, its FdBlock or, for a contact a lane
    // law stepped, its LaneResult (the same names)
    // (Inlined into its callers: through the closure, every array above costs a load.)
    auto finishContact = [&](auto mode, std::size_t i, const PairEntry& e, auto& fd, bool first,
                             ForceThreadPart* part) __attribute__((always_inline)) {
        constexpr int kMode = decltype(mode)::value;
        constexpr bool kFdBlock = std::is_same_v<std::decay_t<decltype(fd)>, FdBlock>;

        Pair& p = pairs[i];
        const ContactGeometry& g = e.g;
        const uint32_t s1 = p.end1;
        const Vec2 x1 = pos[s1];
        const double r1 = radius[s1];
        double placed = 0.0;
        const bool placement = first && cold[i].born_overlapped;
        if constexpr (kFdBlock) {  // (a lane law reports no failure and runs no first touch)
            if (fd.status != 0) reportFailedLaw(world, p, fd);
            if (placement) placed = notePlacement(world, p, cold[i], g.overlap, fd, kEnergy);
        }
        // Non-finite output: summed here, checked once after the loop (findNonFiniteContact).
        (kMode == Parallel::value ? part->finite_check : finite_check) +=
            fd.n_force + fd.s_force + fd.moment + fd.knest + fd.ksest;
        const double fn_old = p.n_force, fs_old = p.s_force, m_old = p.moment;

        // ---- forces onto the ends
        const Vec2 r1c = g.point - x1;
        const Vec2 f = fd.n_force * g.normal + fd.s_force * perp(g.normal);
        const double moment1 = cross(r1c, f) + fd.moment;
        if constexpr (kMode == Direct::value) {
            force[s1] -= f;
            moment[s1] -= moment1;
        } else {
            double* add = actions[i].add[0];
            add[0] = -f.x(), add[1] = -f.y(), add[2] = -moment1;
            add[3] = -0.0, add[4] = -0.0, add[5] = -0.0;  // (a wall pair's end 2 is no ball)
        }
        if (!p.wall) {
            const double moment2 = cross(g.point - e.x2, f) + fd.moment;
            if constexpr (kMode == Direct::value) {
                force[p.end2] += f;
                moment[p.end2] += moment2;
            } else {
                double* add = actions[i].add[1];
                add[0] = f.x(), add[1] = f.y(), add[2] = moment2;
            }
        } else {
            // (wall pairs are the serial part's alone when threads run)
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
                const double arm2_sq = p.wall ? 0.0 : (g.point - e.x2).squaredNorm();
                if constexpr (kMode == Direct::value) {
                    noteContact(world, p, c, fd.knest, fd.ksest, fd.krest, r1c.squaredNorm(),
                                arm2_sq, p.mass_eff);
                } else {
                    // noteContact's stiffness sums, term by term, for the gather
                    double* add = stiffness[i].add[0];
                    add[0] = add[2] = fd.knest + fd.ksest;
                    add[1] = fd.ksest * r1c.squaredNorm() + fd.krest;
                    add[3] = fd.ksest * arm2_sq + fd.krest;
                    noteContactLimits(
                        world, p, c, fd.knest, p.mass_eff,
                        kMode == Parallel::value ? part->limits : world.stepping.limits);
                }
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
                    if constexpr (kMode == Parallel::value) {
                        DeferredItem item{static_cast<uint32_t>(i), Deferred::Contract};
                        item.flags = static_cast<uint32_t>(part->contracts.size());
                        part->items.push_back(item);
                        part->contracts.push_back(
                            {asFdBlock(fd, fd_template), fn_old, fs_old, m_old, c.strain, c.bond});
                    } else {
                        checkEnergyContract(world, p, c.strain, c.bond, asFdBlock(fd, fd_template),
                                            fn_old, fs_old, m_old, totals_before);
                    }
                }
                PairEnergy pe;
                pe.what = PairEnergy::kContact;
                if (placement) pe.what |= PairEnergy::kPlacement, pe.placement = placed;
                pe.slip = fd.energy[kEnergySlip];
                pe.dashpot = fd.energy[kEnergyDashpot];
                pe.plastic = fd.energy[kEnergyPlastic];
                // A break releases what the bond held (accuracy-reference 3.6, pitfall 2; the
                // model says how much), and so does the end of a contact that is still loaded.
                pe.released = fd.energy[kEnergyReleased];
                c.strain = fd.energy[kEnergyStrain];
                c.bond = fd.energy[kEnergyBondStrain];
                if (world.books.strain_baseline_pending && !first) {
                    pe.held = storedBefore(fd, fn_old, fs_old, m_old);
                    pe.what |= PairEnergy::kHeld;
                }
                if (ends) {
                    pe.released_end = c.strain + c.bond;
                    pe.what |= PairEnergy::kEnds;
                } else {
                    pe.strain = c.strain;
                    pe.bond = c.bond;
                    pe.what |= PairEnergy::kStored;
                }
                if constexpr (kMode == Direct::value)
                    bookPairEnergy(pe);
                else
                    energies[i] = pe;
                // Group shares and the work across group borders (group_energy.cpp): one
                // branch per contact, taken only with groups traced (one thread).
                // (lanes do not run while groups are traced)
                if constexpr (kFdBlock)
                    if (groups) bookContactToGroups(world, i, fd, first, ends, pe.held, f, g.point);
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
                p.work += 0.5 * (world.clock.window * power_old + dt * power_new);
                if (ends) p.work += 0.5 * dt * power_new;  // the rest of the last force's work
                p.work_peak = std::max(p.work_peak, p.work);
                // The deepest overlap is where the overlap stops growing: note the previous
                // step's values there, once per turn (the stiffness and resolution checks).
                const bool growing = first || g.overlap > p.overlap;
                if (!growing && p.loading) noteDeepest(world, p, cold[i], fn_old, fd.u_dot_n);
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
                reportPassThrough(world, p, g);
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
        if constexpr (kMode == Parallel::value) {
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
            if (ends) endAndCheck(i);
        }
    };

    // The contact objects live apart from the pairs, which only point to them: ask for the
    // first three cache lines of the object a few pairs ahead of pair i (the shipped models'
    // objects are 88 to 184 bytes).
    auto prefetchModel = [&](std::size_t i, std::size_t end) __attribute__((always_inline)) {
        if (i + kPrefetchAhead >= end) return;
        const Pair& ahead = pairs[i + kPrefetchAhead];
        if (!ahead.active || ahead.lane != kNoLane) return;  // (a lane contact's object rests)
        const char* obj = reinterpret_cast<const char*>(ahead.model);
        __builtin_prefetch(obj);
        __builtin_prefetch(obj + 64);
        __builtin_prefetch(obj + 128);
    };

    // ---- pass 2 for a contact: the batched law with a count of one (no virtual call, the same
    // bits as FDlaw), or FDlaw
    auto runLaw = [&](const Pair& p, FdBlock& fd, std::string& error, int64_t& batched_count)
        __attribute__((always_inline)) {
        const BatchFdLawFn batch = batched ? p.rule->batch : nullptr;
        if (batch) {
            ContactModel* model = p.model;
            batch(&model, &fd, 1);
            ++batched_count;
        } else {
            callLaw(p.model, fd, error);
        }
    };

    // ---- after a contact's FDlaw and finish (one thread, or the threads' serial part): into its
    // rule's lanes, if its model has a lane law that takes it now (docs/plugin-abi.md, "Lanes")
    auto offerLane = [&](Pair& p) {
        if (lanes_on && p.active && p.lane == kNoLane && laneable(p)) enterLane(p);
    };

    // ---- a rare pair, alone (never in a thread's range); returns the next pair to process.
    // Pass 1 left its geometry in `e` and its FdBlock in `fd`.
    auto processRare = [&](auto mode, std::size_t i, PairStep stop, PairEntry& e, FdBlock& fd,
                           std::string& error) -> std::size_t {
        if (stop == PairStep::HandOver) {
            // The contact crossed a convex vertex and moves, state and all, to the holder's
            // pair, which now sits in slot i: process slot i again (a pair may have been
            // created).
            if (handOverWallContact(world, i)) return i;
            // No pair can take it (no holder, or one with a contact of its own): the contact
            // ends here, and what it still stores is released.
            Pair& p = pairs[i];
            const double stored = cold[i].strain + cold[i].bond;
            if constexpr (kEnergy) {
                if constexpr (decltype(mode)::value == Direct::value)
                    world.books.acc.released += stored;
                if (groups) bookReleasedToGroups(world, p, stored);
            }
            endContact(world, p, cold[i], kGuard);
            finishApart(mode, i, PairStep::Elsewhere, nullptr);
            if constexpr (kEnergy && decltype(mode)::value != Direct::value) {
                energies[i] = PairEnergy{};
                energies[i].what = PairEnergy::kHandOver;
                energies[i].released_end = stored;
            }
            return i + 1;
        }
        // A pair touching for the first time: activate it, then its law (FDlaw, and the first
        // call's flags), then its finish.
        Pair& p = pairs[i];
        const bool first = activate(world, p, cold[i], e.g, e.vrel);
        if (first) {
            fd.flags |= kFdFirstCall | world.contacts.activation_flags;
        } else {
            // A wall pair that took over its chain's contact from a neighbouring segment's pair
            // (activate, adoptWallContact): the forces are that contact's.
            fd.n_force = p.n_force;
            fd.s_force = p.s_force;
            fd.moment = p.moment;
        }
        callLaw(p.model, fd, error);
        finishContact(mode, i, e, fd, first, nullptr);
        offerLane(p);
        return i + 1;
    };

    // ---- one pair, all three passes, on one thread (Direct) or in the threads' serial part;
    // returns the next pair to process
    auto runPair = [&](auto mode, std::size_t i, std::size_t end, PairEntry& e, FdBlock& fd,
                       std::string& error, int64_t& batched_count) __attribute__((always_inline))
                       ->std::size_t {
        prefetchModel(i, end);
        const PairStep step = geometry(i, e, &fd);
        if (step == PairStep::Contact) {
            Pair& p = pairs[i];
            runLaw(p, fd, error, batched_count);
            finishContact(mode, i, e, fd, false, nullptr);
            offerLane(p);
            return i + 1;
        }
        if (step == PairStep::Apart || step == PairStep::Elsewhere) {
            finishApart(mode, i, step, nullptr);
            return i + 1;
        }
        return processRare(mode, i, step, e, fd, error);
    };

    // ---- a block of pairs through the lanes (docs/plugin-abi.md, "Lanes"): up to kBlock pairs
    // from i that are contacts in the lanes of one rule or pairs apart, in three passes: the
    // geometry of every pair, with the contacts' inputs into the rule's LaneBatch; one call of
    // the lane law for them all (a contact it declines goes through FDlaw); the finish of every
    // pair in pair order, as runPair does it. Stops before a wall pair, a contact outside the
    // lanes or of another rule, and a pair that touches for the first time. Returns the first
    // pair after the block: i when the pair at i is none of these. `at` follows the pair being
    // finished (the threads' failure point).
    auto runLaneBlock = [&](auto mode, std::size_t i, std::size_t end, LaneScratch& ls,
                            ForceThreadPart* part, std::string& error, LaneCounts& counts,
                            std::size_t& at) -> std::size_t {
        LaneTable* table = nullptr;
        std::size_t row_bytes = 0;
        int n = 0, nb = 0;
        for (std::size_t j = i; j < end && n < LaneScratch::kBlock; ++j) {
            const Pair& p = pairs[j];
            if (p.wall) break;
            if (p.active) {
                if (p.lane == kNoLane || (table && p.rule->lanes.get() != table)) break;
                if (!table) {
                    table = p.rule->lanes.get();
                    row_bytes = sizeof(double) * std::size_t(table->law().state_size);
                }
            }
            PairEntry& e = ls.entry[n];
            const PairStep step = geometry(j, e, nullptr);
            if (step == PairStep::Touch) break;
            ls.step[n] = step;
            if (step == PairStep::Contact) {
                // (its row is wanted by the law after the block's geometry: ask for it now)
                const char* row = reinterpret_cast<const char*>(table->row(p.lane));
                for (std::size_t at_byte = 0; at_byte < row_bytes; at_byte += 64)
                    __builtin_prefetch(row + at_byte, 1);
                ls.slot[n] = nb;
                ls.row[nb] = p.lane;
                ls.u_n[nb] = e.g.overlap;
                ls.u_dot_n[nb] = e.u_dot_n;
                ls.u_dot_s[nb] = e.u_dot_s;
                ls.t_dot_rel[nb] = e.t_dot_rel;
                ls.mass_eff[nb] = p.mass_eff;
                ls.inv_mass_eff_s[nb] = p.inv_mass_eff_s;
                ls.n_force[nb] = p.n_force;
                ls.s_force[nb] = p.s_force;
                ls.moment[nb] = p.moment;
                ++nb;
            }
            ++n;
        }
        if (nb > 0) {
            LaneBatch& batch = ls.batch;
            batch.flags = fd_template.flags;
            batch.count = nb;
            batch.tdel = dt;
            batch.time = fd_template.time;
            batch.state = table->state();
            table->law().law(batch);
            counts.steps += nb;
            // Declined: the object up to date, FDlaw, and back into its row if the model takes
            // it (the row is freed serially when threads run).
            for (int q = 0; q < n; ++q) {
                if (ls.step[q] != PairStep::Contact) continue;
                const int k = ls.slot[q];
                if (!(ls.flags_out[k] & kFdLaneDeclined)) continue;
                ++counts.declined;
                Pair& p = pairs[i + static_cast<std::size_t>(q)];
                table->law().unpack(p.model, table->row(p.lane));
                FdBlock& fd = ls.declined[static_cast<std::size_t>(k)];
                fd = fd_template;
                const PairEntry& e = ls.entry[q];
                fillFd(p, e.g.overlap, e.u_dot_n, e.u_dot_s, e.t_dot_rel, fd);
                runLaw(p, fd, error, counts.batched);
                if (table->law().pack(p.model, table->row(p.lane)) == 0) {
                    if constexpr (decltype(mode)::value == Parallel::value)
                        part->lane_releases.emplace_back(table, p.lane);
                    else
                        table->release(p.lane);
                    p.lane = kNoLane;
                }
            }
        }
        for (int q = 0; q < n; ++q) {
            const std::size_t j = i + static_cast<std::size_t>(q);
            at = j;
            if (ls.step[q] != PairStep::Contact) {
                finishApart(mode, j, ls.step[q], part);
                continue;
            }
            const int k = ls.slot[q];
            if (ls.flags_out[k] & kFdLaneDeclined) {
                finishContact(mode, j, ls.entry[q], ls.declined[static_cast<std::size_t>(k)], false,
                              part);
            } else {
                LaneResult r = ls.result(k, dt);
                finishContact(mode, j, ls.entry[q], r, false, part);
            }
        }
        return i + static_cast<std::size_t>(n);
    };

    if (nthreads <= 1) {
        PairEntry e;
        FdBlock fd = fd_template;
        LaneCounts counts;
        LaneScratch& ls = scratch.lanes;
        if (lanes_on) ls.prepare();
        std::size_t at = 0;
        if (lanes_on) {
            for (std::size_t i = 0; i < npairs;) {
                const std::size_t next =
                    runLaneBlock(Direct{}, i, npairs, ls, nullptr, scratch.error, counts, at);
                i = next != i ? next
                              : runPair(Direct{}, i, npairs, e, fd, scratch.error, counts.batched);
            }
        } else {
            for (std::size_t i = 0; i < npairs;)
                i = runPair(Direct{}, i, npairs, e, fd, scratch.error, counts.batched);
        }
        world.profile.batched_laws += counts.batched;
        world.profile.lane_steps += counts.steps;
        world.profile.lane_declined += counts.declined;
    } else {
#ifdef TALUS_HAVE_OPENMP
        ++world.profile.threaded_steps;
        auto& parts = scratch.parts;
        // ---- the threads' ranges: contiguous, of equal pair counts
#pragma omp parallel num_threads(nthreads)
        {
            const int t = omp_get_thread_num();
            ForceThreadPart& part = parts[static_cast<std::size_t>(t)];
            const std::size_t lo = npairs * static_cast<std::size_t>(t) / nthreads;
            const std::size_t hi = npairs * static_cast<std::size_t>(t + 1) / nthreads;
            std::size_t i = lo;
            try {
                PairEntry e;
                LaneCounts counts;
                if (lanes_on) part.lanes.prepare();
                while (i < hi) {
                    if (lanes_on) {
                        std::size_t at = i;
                        try {
                            const std::size_t next = runLaneBlock(Parallel{}, i, hi, part.lanes,
                                                                  &part, part.error, counts, at);
                            if (next != i) {
                                i = next;
                                continue;
                            }
                        } catch (...) {
                            i = at;
                            throw;
                        }
                    }
                    prefetchModel(i, hi);
                    if (pairs[i].wall) {
                        part.items.push_back({static_cast<uint32_t>(i), Deferred::Pair});
                        ++i;
                        continue;
                    }
                    const PairStep step = geometry(i, e, &part.fd);
                    if (step == PairStep::Contact) {
                        Pair& p = pairs[i];
                        runLaw(p, part.fd, part.error, counts.batched);
                        finishContact(Parallel{}, i, e, part.fd, false, &part);
                        if (lanes_on && p.lane == kNoLane && laneable(p))
                            part.lane_entries.push_back(static_cast<uint32_t>(i));
                    } else if (step == PairStep::Apart) {
                        finishApart(Parallel{}, i, step, &part);
                    } else {  // Touch
                        part.items.push_back({static_cast<uint32_t>(i), Deferred::Pair});
                    }
                    ++i;
                }
                part.batched = counts.batched;
                part.lane_steps = counts.steps;
                part.lane_declined = counts.declined;
            } catch (...) {
                part.failure = std::current_exception();
                part.failure_pair = i;
            }
        }
        // ---- the serial part: the threads' deferred work in pair order, up to the first pair
        // that failed (as one thread would have stopped there)
        std::size_t failed = SIZE_MAX;
        const ForceThreadPart* failed_part = nullptr;
        for (const auto& part : parts)
            if (part.failure && part.failure_pair < failed)
                failed = part.failure_pair, failed_part = &part;
        PairEntry e;
        FdBlock& fd = parts[0].fd;
        int64_t batched_count = 0;
        for (auto& part : parts) {
            for (const DeferredItem& item : part.items) {
                const std::size_t i = item.pair;
                if (i >= failed) break;
                switch (item.kind) {
                    case Deferred::Pair:
                        // (a vertex hand-over leaves the contact's new holder in slot i: again)
                        for (std::size_t next = i; next == i;)
                            next =
                                runPair(Serial{}, i, npairs, e, fd, scratch.error, batched_count);
                        break;
                    case Deferred::Break:
                        queueBreak(world, i, item.point, item.break_mode,
                                   (item.flags & kFdBreakStress) != 0, item.sigma, item.tau);
                        break;
                    case Deferred::End:
                        endAndCheck(i);
                        break;
                    case Deferred::Remove:
                        to_remove.push_back(static_cast<uint32_t>(i));
                        break;
                    case Deferred::Contract: {
                        const ContractNote& note = part.contracts[item.flags];
                        checkEnergyContract(world, pairs[i], note.strain_old, note.bond_old,
                                            note.fd, note.fn_old, note.fs_old, note.m_old,
                                            totals_before);
                        break;
                    }
                }
            }
            finite_check += part.finite_check;
            batched_count += part.batched;
            world.profile.lane_steps += part.lane_steps;
            world.profile.lane_declined += part.lane_declined;
            if constexpr (kAuto) world.stepping.limits.merge(part.limits);
        }
        world.profile.batched_laws += batched_count;
        // The lanes' rows the threads let go, then the contacts they offer (in pair order).
        for (auto& part : parts)
            for (const auto& [table, row] : part.lane_releases) table->release(row);
        for (auto& part : parts)
            for (const uint32_t i : part.lane_entries)
                if (i < failed) offerLane(pairs[i]);
        if (failed_part) std::rethrow_exception(failed_part->failure);
        gatherPairActions(world, nthreads, kAuto);
        if constexpr (kEnergy)
            for (std::size_t i = 0; i < npairs; ++i)
                if (energies[i].what) bookPairEnergy(energies[i]);
#endif
    }
    if constexpr (kAuto) {
        noteApproaches(world, scratch.apart, world.stepping.limits);
        if (nthreads > 1)
            for (const auto& part : scratch.parts)
                noteApproaches(world, part.apart, world.stepping.limits);
    }

    if (!std::isfinite(finite_check)) findNonFiniteContact(world);
    for (auto it = to_remove.rbegin(); it != to_remove.rend(); ++it) removePair(world, *it);
    clearMovedFlags(world);
    if constexpr (kEnergy) {
        world.books.acc.strain = strain_now;
        world.books.acc.bond = bond_now;
        if (groups) groupForceLoopEnd(world);
        if (world.books.strain_baseline_pending) {
            // Tracing was switched on with loaded contacts: what they hold was put in before
            // the books opened (bookkeeping.cpp, setEnergyTracing).
            world.books.acc.initial_strain = held_before;
            world.books.strain_baseline_pending = false;
        }
    }
}

}  // namespace

void noteApproaches(const World& world, const std::vector<uint32_t>& apart, StepLimits& limits) {
    const auto& b = world.bodies.balls;
    const auto& pairs = world.contacts.pairs;
    const auto& cold = world.contacts.cold;
    for (const uint32_t i : apart) {
        const Pair& p = pairs[i];
        const uint32_t s1 = p.end1;
        if (!p.wall) {
            const uint32_t s2 = p.end2;
            const Vec2 d = b.pos[s2] - b.pos[s1];
            const double dist = d.norm();
            const Vec2 arel = (b.force[s2] + b.fapp[s2]) * b.inv_mass[s2] -
                              (b.force[s1] + b.fapp[s1]) * b.inv_mass[s1];
            noteApproach(world, p, cold[i], dist - (b.radius[s1] + b.radius[s2]),
                         b.vel[s2] - b.vel[s1], arel.norm(),
                         dist > 0.0 ? Vec2(d / dist) : Vec2(0.0, 1.0), limits);
        } else {
            // (the pair was Apart: its ball is in this segment's region)
            ContactGeometry g;
            if (!segmentGeometry(world, p.end2, b.pos[s1], b.radius[s1], g)) continue;
            const WallData& wall = world.bodies.walls[world.bodies.segments[p.end2].wall];
            const Vec2 v2c = wall.vel + spinCross(wall.spin, g.point - wall.center);
            const Vec2 a1 = (b.force[s1] + b.fapp[s1]) * b.inv_mass[s1] + world.settings.gravity;
            noteApproach(world, p, cold[i], -g.overlap, v2c - b.vel[s1], a1.norm(), g.normal,
                         limits);
        }
    }
}

void gatherPairActions(World& world, int nthreads, bool automatic) {
    auto& b = world.bodies.balls;
    const ForceScratch& s = world.contacts.force_scratch;
    const PairAction* actions = s.actions.data();
    const PairStiffness* stiffness = s.stiffness.data();
    const uint32_t* start = s.incidence_start.data();
    const uint32_t* incidence = s.incidence.data();
    Vec2* force = b.force.data();
    double* moment = b.moment.data();
    double* k_tran = b.k_tran.data();
    double* k_rot = b.k_rot.data();
    const auto nballs = static_cast<std::ptrdiff_t>(b.size());
    (void)nthreads;
    // Each ball's sums start from zero and take its pairs in pair order: the additions one
    // thread makes (finishContact), in its order (PairAction).
    TALUS_OMP(omp parallel for num_threads(nthreads) schedule(static))
    for (std::ptrdiff_t k = 0; k < nballs; ++k) {
        double fx = 0.0, fy = 0.0, m = 0.0;
        for (uint32_t q = start[k]; q < start[k + 1]; ++q) {
            const uint32_t code = incidence[q];
            const double* add = actions[code >> 1].add[code & 1u];
            fx += add[0];
            fy += add[1];
            m += add[2];
        }
        force[k] = Vec2(fx, fy);
        moment[k] = m;
        if (automatic) {
            double kt = 0.0, kr = 0.0;
            for (uint32_t q = start[k]; q < start[k + 1]; ++q) {
                const uint32_t code = incidence[q];
                const double* add = stiffness[code >> 1].add[code & 1u];
                kt += add[0];
                kr += add[1];
            }
            k_tran[k] = kt, k_rot[k] = kr;
        }
    }
}

void buildIncidence(World& world) {
    ForceScratch& s = world.contacts.force_scratch;
    const auto& pairs = world.contacts.pairs;
    const std::size_t nballs = world.bodies.balls.size();
    if (s.incidence_version == world.contacts.pairs_version &&
        s.incidence_start.size() == nballs + 1)
        return;
    if (pairs.size() >= (std::size_t{1} << 31))
        throw InputError("threads: more than 2^31 pairs (run on one thread)");
    auto& start = s.incidence_start;
    start.assign(nballs + 1, 0u);
    for (const Pair& p : pairs) {
        ++start[p.end1 + 1];
        if (!p.wall) ++start[p.end2 + 1];
    }
    for (std::size_t k = 0; k < nballs; ++k) start[k + 1] += start[k];
    s.incidence.resize(start[nballs]);
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const auto code = static_cast<uint32_t>(i << 1);
        s.incidence[fill[pairs[i].end1]++] = code;
        if (!pairs[i].wall) s.incidence[fill[pairs[i].end2]++] = code | 1u;
    }
    s.incidence_version = world.contacts.pairs_version;
}

// ------------------------------------------------------------------------ threads

void Model::setThreads(int n, int grain) {
    World& world = *m_world;
    if (n < 1 || n > 1024)
        throw InputError("threads: the thread count must be from 1 to 1024 (got " +
                         std::to_string(n) + ")");
    if (grain < 1)
        throw InputError("threads: the grain (fewest pairs per thread) must be >= 1 (got " +
                         std::to_string(grain) + ")");
    world.settings.threads = n;
    world.settings.thread_grain = grain;
}

int Model::threads() const {
    const World& world = *m_world;
    if (world.settings.threads > 0) return world.settings.threads;
    // TALUS_THREADS (talus run --threads N sets it): a bad value is the CLI's to refuse; here
    // it falls back to one thread.
    const char* env = std::getenv("TALUS_THREADS");
    if (!env || !*env) return 1;
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    return (*end == '\0' && n >= 1 && n <= 1024) ? static_cast<int>(n) : 1;
}

int Model::threadGrain() const {
    const World& world = *m_world;
    if (world.settings.thread_grain > 0) return world.settings.thread_grain;
    // TALUS_THREAD_GRAIN: for tests that run small scenes on threads (stress suite).
    const char* env = std::getenv("TALUS_THREAD_GRAIN");
    if (!env || !*env) return kDefaultThreadGrain;
    char* end = nullptr;
    const long g = std::strtol(env, &end, 10);
    return (*end == '\0' && g >= 1 && g <= 1000000000) ? static_cast<int>(g) : kDefaultThreadGrain;
}

namespace {
bool g_single_threaded_process = false;  // Model::singleThreadedProcess
}  // namespace

void Model::singleThreadedProcess() { g_single_threaded_process = true; }

bool Model::threadingAvailable() {
#ifdef TALUS_HAVE_OPENMP
    return true;
#else
    return false;
#endif
}

int Model::forceThreads(std::size_t npairs) const { return talus::forceThreads(*m_world, npairs); }

int forceThreads(const World& world, std::size_t npairs) {
#ifdef TALUS_HAVE_OPENMP
    const int wanted = world.facade.threads();
    if (wanted <= 1 || g_single_threaded_process) return 1;
    const std::size_t by_grain = npairs / static_cast<std::size_t>(world.facade.threadGrain());
    const int n =
        static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(wanted), by_grain));
    if (n < 2) return 1;
    // Energy per group books every contact into its groups' sums and border records as it
    // goes: one thread (docs/architecture.md, "Threads").
    if (world.books.on && world.books.groups.on) return 1;
    for (const auto& rule : world.contacts.rules)
        if (rule->prototype && !(rule->prototype->Traits() & kTraitThreadSafe)) return 1;
    return n;
#else
    (void)world;
    (void)npairs;
    return 1;
#endif
}

void prepareForceScratch(World& world, int nthreads, const FdBlock& tmpl) {
    ForceScratch& s = world.contacts.force_scratch;
    s.parts.resize(static_cast<std::size_t>(nthreads));
    for (auto& part : s.parts) {
        part.fd = tmpl;
        part.items.clear();
        part.apart.clear();
        part.limits = StepLimits{};
        part.finite_check = 0.0;
        part.batched = 0;
        part.failure = nullptr;
        part.failure_pair = SIZE_MAX;
        part.lane_entries.clear();
        part.lane_releases.clear();
        part.lane_steps = part.lane_declined = 0;
    }
    // (pairs a vertex hand-over adds in this step are not processed in it: npairs is enough)
    s.actions.resize(world.contacts.pairs.size());
    if (world.settings.timestep.automatic) s.stiffness.resize(world.contacts.pairs.size());
    if (world.books.on) s.energies.resize(world.contacts.pairs.size());
    for (auto& part : s.parts) part.contracts.clear();
    buildIncidence(world);
}

// The rare paths of the loop, kept out of it so that its body stays small.

bool activate(World& world, Pair& p, PairCold& c, const ContactGeometry& g, const Vec2& vrel) {
    // A wall pair may be taking over the ball's contact from a neighbouring segment's pair
    // (a convex vertex crossed, that pair later in the loop): then the contact goes on.
    if (p.wall && adoptWallContact(world, world.contacts.pairIndex(p))) return false;
    if (c.rules_version != world.contacts.rules_version) refreshRule(world, p);
    // A pair whose bond broke or was removed is not bonded again by a rule (model_bonds.cpp);
    // the lookup runs only in a model where that happened.
    world.contacts.activation_flags =
        world.contacts.unbonded.empty() ? 0u : autoBondFlags(world, p, c);
    p.active = true;
    ++world.profile.contacts_created;
    c.duration = p.model->ContactDuration(p.mass_eff, std::max(0.0, -vrel.dot(g.normal)));
    // The resolution rule and the guard divide by it: NaN, zero or negative would silently
    // switch both off (docs/plugin-abi.md, time-step contract). +inf means "no force".
    if (!(c.duration > 0.0))
        throw PluginError("contact model '" + p.rule->model_name + "' at step " +
                          std::to_string(world.clock.step) + " on " + describePair(world, p) +
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
            talus::warn(
                world,
                "contact model '" + p.rule->model_name + "' has no normal stiffness on " +
                    describePair(world, p) + " (" + zero + ")" +
                    ": the bodies will pass through each other; set the stiffness in "
                    "m:contact_model{...} or on the bodies (warned once per contact_model rule)");
    }
    // For the guard: a contact born overlapping (placed so) gives back energy it never took.
    // How much of the overlap the last step's motion made. Positions at the previous step are
    // x - v dt exactly (the half-step velocity moved them), so for two balls the overlap then
    // is known exactly; for a wall, the normal closing plus the turn of the line from the
    // vertex or the face, (v_t dt)^2 / (2 r). (The contact-point velocity would add the spins,
    // which turn the balls but do not close the gap.) More overlap than that was there before.
    const auto& b = world.bodies.balls;
    const double approach = -vrel.dot(g.normal);
    c.approach_rate = std::max(approach, 0.0);
    if (!p.wall) {
        const Vec2 d = b.pos[p.end2] - b.pos[p.end1];
        const Vec2 step = (b.vel[p.end2] - b.vel[p.end1]) * world.clock.dt;
        const double rsum = b.radius[p.end1] + b.radius[p.end2];
        c.closure = std::max(g.overlap - (rsum - (d - step).norm()), 0.0);
    } else {
        const WallData& w = world.bodies.walls[world.bodies.segments[p.end2].wall];
        const Vec2 step =
            (w.vel + spinCross(w.spin, g.point - w.center) - b.vel[p.end1]) * world.clock.dt;
        const double slide = step.dot(perp(g.normal));
        c.closure = std::max(-step.dot(g.normal), 0.0) + slide * slide / (2.0 * b.radius[p.end1]);
    }
    c.born_overlapped = g.overlap > c.closure * (1.0 + 1e-9) + 1e-15;
    if (world.callbacks.contact_events) {
        Event ev;
        ev.kind = EventKind::ContactCreated;
        ev.time = world.clock.time;
        ev.pos = g.point;
        ev.contact = ContactKey{c.key};
        ev.model = p.rule->model_name;
        world.callbacks.events.push_back(std::move(ev));
    }
    return true;
}

void checkEnergyContract(World& world, const Pair& p, double strain_old, double bond_old,
                         const FdBlock& fd, double fn_old, double fs_old, double m_old,
                         const EnergyTotals& before) {
    const double scale = std::fabs(strain_old) + std::fabs(bond_old) +
                         std::fabs(fd.energy[kEnergyStrain]) +
                         std::fabs(fd.energy[kEnergyBondStrain]) +
                         (std::fabs(fn_old) + std::fabs(fd.n_force)) * std::fabs(fd.du_n) +
                         (std::fabs(fs_old) + std::fabs(fd.s_force)) * std::fabs(fd.du_s) +
                         (std::fabs(m_old) + std::fabs(fd.moment)) * std::fabs(fd.dtheta);
    const double totals[kEnergyCount] = {0.0, before.slip, before.dashpot, before.plastic,
                                         0.0, 0.0};
    const std::string why = energyContractViolation(fd, scale, totals);
    if (!why.empty()) {
        const std::string what = "contact model '" + p.rule->model_name + "' at step " +
                                 std::to_string(world.clock.step) + " on " +
                                 describePair(world, p) + ": " + why;
        // NaN stops the run. A negative total warns once per rule: contacts
        // born overlapping and the half-step settling at separation make it
        // happen in sound runs (docs/plugin-abi.md, "Energies").
        if (why.compare(0, 9, "negative ") != 0) throw PluginError(what);
        if (!p.rule->warned_negative_dissipation) {
            p.rule->warned_negative_dissipation = true;
            talus::warn(world, what + " (warned once per contact_model rule)");
        }
    }
}

double notePlacement(World& world, const Pair& p, const PairCold& c, double overlap,
                     const FdBlock& fd, bool energy) {
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
    world.books.last_placed = placed;
    // Below a thousandth of the radius it is bookkeeping, not a user's placement (a contact
    // formed by a spin-driven slide, rounding). Booked, not reported.
    const auto& b = world.bodies.balls;
    const double r = p.wall ? b.radius[p.end1] : std::min(b.radius[p.end1], b.radius[p.end2]);
    if (overlap < 1e-3 * r) return placed;
    world.guard_state.placed_energy += placed;
    if (world.guard_state.placed++ == 0) {
        world.guard_state.placed_first = describePair(world, p) + " at step " +
                                         std::to_string(world.clock.step) + ": overlap " +
                                         num(overlap) + " m (" + num(100.0 * overlap / r) +
                                         "% of the smaller radius), stored energy " + num(placed) +
                                         " J" + (energy ? "" : " (estimated from knest)");
    }
    return placed;
}

void noteDeepest(World& world, const Pair& p, PairCold& c, double force, double rate_after) {
    if (p.overlap <= c.overlap_max) return;
    c.overlap_max = p.overlap;
    c.force_at_max = force;
    c.rate_at_max = rate_after;
    c.knest_at_max = p.knest;
    c.dt_at_max = world.clock.dt;
}

void queueBreak(World& world, std::size_t i, const Vec2& point, const FdBlock& fd) {
    queueBreak(world, i, point, fd.break_mode, (fd.flags & kFdBreakStress) != 0, fd.reserved[0],
               fd.reserved[1]);
}

void queueBreak(World& world, std::size_t i, const Vec2& point, int32_t mode, bool with_stress,
                double sigma, double tau) {
    forgetBond(world, i);
    Event ev;
    ev.kind = EventKind::BondBreak;
    ev.time = world.clock.time;
    ev.pos = point;
    ev.contact = ContactKey{world.contacts.cold[i].key};
    ev.mode = mode;
    ev.model = world.contacts.pairs[i].rule->model_name;
    if (with_stress) {
        ev.sigma = sigma;
        ev.tau = tau;
    }
    world.callbacks.events.push_back(std::move(ev));
}

void reportFailedLaw(const World& world, const Pair& p, const FdBlock& fd) {
    throw PluginError("contact model '" + p.rule->model_name + "' failed at step " +
                      std::to_string(world.clock.step) + " on " + describePair(world, p) + ": " +
                      (fd.error ? fd.error : "(no message)"));
}

void findNonFiniteContact(const World& world) {
    // The force loop only sums the models' outputs; find the first contact that made the sum
    // non-finite (its stored values are this step's).
    for (const Pair& p : world.contacts.pairs)
        if (p.active && !std::isfinite(p.n_force + p.s_force + p.moment + p.knest + p.ksest))
            throwNonFinite(world, describePair(world, p) + ": FDlaw returned normal force " +
                                      num(p.n_force) + ", shear force " + num(p.s_force) +
                                      ", moment " + num(p.moment) + ", knest " + num(p.knest) +
                                      ", ksest " + num(p.ksest) + " at overlap " + num(p.overlap));
    throwNonFinite(
        world, "a contact model returned a non-finite value (the contact ended in the same step)");
}

void reportPassThrough(const World& world, const Pair& p, const ContactGeometry& g) {
    throw NumericalError("at step " + std::to_string(world.clock.step) +
                         " (t = " + num(world.clock.time) + " s): " + describePair(world, p) +
                         ": the contact normal reversed within one step, so one body passed "
                         "through the other (overlap " +
                         num(g.overlap) +
                         " m); the contact is too soft for this impact or the step too large");
}

void endContact(World& world, Pair& p, PairCold& c, bool check_guard) {
    if (check_guard && p.steps > 0 && p.steps <= kGuardWatch) {
        // A contact created overlapping (by placement) gives back energy it never took.
        // Reference: the larger of the energy the contact held at its peak and the kinetic
        // energy of the approach (a contact that only ever gave energy has no peak).
        const double reference =
            std::max(p.work_peak, 0.5 * p.mass_eff * c.approach_rate * c.approach_rate);
        if (world.settings.guard.energy != GuardAction::Off && !c.born_overlapped &&
            reference > 0.0 && p.work < -world.settings.guard.energy_tolerance * reference) {
            const std::string what =
                describePair(world, p) + " returned " + num(-p.work) +
                " J more than it took (reference " + num(reference) + " J, tolerance " +
                num(100.0 * world.settings.guard.energy_tolerance) + "%) over " +
                std::to_string(p.steps) + " steps ending at t = " + num(world.clock.time) +
                " s; the step (" + num(world.clock.dt) +
                " s) is too large for the model's stiffness, or the "
                "model reports too low a stiffness (knest " +
                num(p.knest) + " N/m)";
            if (world.settings.guard.energy == GuardAction::Error)
                throw NumericalError("energy created: " + what);
            if (world.guard_state.energy_gain++ == 0) world.guard_state.energy_gain_first = what;
        }
        // Under-resolved: a step taken during the contact was too large for the impact's own
        // duration (the model's estimate at touch). A contact that is short for other reasons
        // (grazing, knocked away) is not a finding; a model that misreports its stiffness is the
        // stiffness check's business.
        if (world.settings.guard.resolution != GuardAction::Off && !p.bonded &&
            c.duration < world.settings.guard.min_steps * c.dt_at_max) {
            const std::string what =
                describePair(world, p) + " had " + num(c.duration / c.dt_at_max) +
                " steps per contact duration (" + num(c.duration) +
                " s at dt = " + num(c.dt_at_max) + " s, t = " + num(world.clock.time) +
                " s); it lasted " + std::to_string(p.steps) + " steps";
            if (world.settings.guard.resolution == GuardAction::Error)
                throw NumericalError("impact under-resolved: " + what + "; at least " +
                                     std::to_string(world.settings.guard.min_steps) +
                                     " steps are needed");
            if (world.guard_state.underresolved++ == 0)
                world.guard_state.underresolved_first = what;
        }
        // At the deepest overlap the force may be up to twice the reported stiffness times the
        // overlap (tangent vs secant), plus what a dashpot up to critical damping gives at the
        // rate there (about zero for a resolved impact, not for a contact in a packing).
        const double secant = c.overlap_max > 0.0 ? c.force_at_max / c.overlap_max : 0.0;
        const double allowed =
            2.0 * c.knest_at_max * c.overlap_max +
            2.0 * std::sqrt(p.mass_eff * c.knest_at_max) * std::fabs(c.rate_at_max);
        if (world.settings.guard.stiffness != GuardAction::Off && !p.bonded &&
            c.force_at_max > allowed) {
            const std::string what =
                describePair(world, p) + ": at its deepest overlap its normal force was " +
                num(secant) + " N/m of overlap while it reported knest " + num(c.knest_at_max) +
                " N/m; the time step follows knest, so the model must report its true tangent "
                "stiffness (docs/plugin-abi.md, time-step contract)";
            if (world.settings.guard.stiffness == GuardAction::Error)
                throw NumericalError("stiffness under-reported: " + what);
            if (world.guard_state.stiffness_lies++ == 0)
                world.guard_state.stiffness_lies_first = what;
        }
    }
    resetPair(world, p);
}

}  // namespace talus
