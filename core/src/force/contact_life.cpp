// SPDX-License-Identifier: MIT
//
// A contact's life beyond the loop's hot path: its first touch (activate: its rule, its expected
// duration, the placement check), a contact born overlapping (notePlacement), its deepest
// overlap (noteDeepest), a bond break (queueBreak) and its end, where the stability guard judges
// it (endContact; docs/physics/guard.md).
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <string>

#include "api/operations.hpp"
#include "force/force.hpp"
#include "props.hpp"
#include "step/detection.hpp"
#include "step/step.hpp"
#include "talus/errors.hpp"
#include "world/lanes.hpp"
#include "world/messages.hpp"

namespace talus {

namespace {
std::string num(double v) { return messageNumber(v); }

/// The half width of the bond a contact's model holds [m]: the first of its properties that
/// name it (a new model's `bond_radius`, PFC's `pb_rad` of a parallel bond, a flat joint's
/// `fj_radius`), NaN when it has none or it is not positive (docs/plugin-abi.md, "Bonds").
double bondRadius(const ContactStore& cs, const Pair& p) {
    static const char* const kNames[] = {"bond_radius", "pb_rad", "fj_radius"};
    if (p.model)
        for (const char* name : kNames) {
            const int32_t k = propIndex(*p.model, name);
            if (k < 0) continue;
            syncLane(cs, p);  // (the model object is current only outside the lanes)
            const double r = p.model->ReturnProp(k);
            return r > 0.0 ? r : std::numeric_limits<double>::quiet_NaN();
        }
    return std::numeric_limits<double>::quiet_NaN();
}
}  // namespace

Touch activate(World& world, Pair& p, PairCold& c, const ContactGeometry& g, const Vec2& vrel,
               bool guard) {
    // A wall pair may be taking over the ball's contact from a neighbouring segment's pair
    // (a convex vertex crossed, that pair later in the loop): then the contact goes on.
    if (p.wall && adoptWallContact(world, world.contacts.pairIndex(p))) return Touch{};
    if (c.rules_version != world.contacts.rules_version) refreshRule(world, p);
    // A pair whose bond broke or was removed is not bonded again by a rule (api/bonds.cpp);
    // the lookup runs only in a model where that happened.
    world.contacts.activation_flags =
        world.contacts.unbonded.empty() ? 0u : autoBondFlags(world, p, c);
    p.active = true;
    ++world.profile.contacts_created;
    c.duration = p.model->ContactDuration(c.mass_eff, std::max(0.0, -vrel.dot(g.normal)));
    // The resolution rule and the guard divide by it: NaN, zero or negative would silently
    // switch both off (docs/plugin-abi.md, time-step contract). +inf means "no force".
    if (!(c.duration > 0.0))
        throw PluginError("contact model '" + world.contacts.ruleOf(p).model_name + "' at step " +
                          std::to_string(world.clock.step) + " on " + describePair(world, p) +
                          ": ContactDuration(mass_eff " + num(c.mass_eff) + " kg, approach " +
                          num(std::max(0.0, -vrel.dot(g.normal))) + " m/s) returned " +
                          num(c.duration) + " s (must be > 0, +inf for no force)");
    // A rule whose contacts have no stiffness at all (m:contact_model("linear") with no kn:
    // the bodies pass through each other) is worth one warning per rule: no tangent stiffness
    // at touch and no finite duration even at 1 m/s means the model exerts no normal force.
    if (!world.contacts.ruleOf(p).warned_no_stiffness && !(p.model->KnEstimate() > 0.0) &&
        !(p.model->ContactDuration(c.mass_eff, 1.0) < HUGE_VAL)) {
        world.contacts.ruleOf(p).warned_no_stiffness = true;
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
                "contact model '" + world.contacts.ruleOf(p).model_name +
                    "' has no normal stiffness on " + describePair(world, p) + " (" + zero + ")" +
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
    Touch touch;
    touch.first = true;
    if (!p.wall) {
        const Vec2 d = b.pos[p.end2] - b.pos[p.end1];
        const Vec2 step = (b.vel[p.end2] - b.vel[p.end1]) * world.clock.dt;
        const double rsum = b.radius[p.end1] + b.radius[p.end2];
        touch.closure = std::max(g.overlap - (rsum - (d - step).norm()), 0.0);
    } else {
        const WallData& w = world.bodies.walls[world.bodies.segments[p.end2].wall];
        const Vec2 step =
            (w.vel + spinCross(w.spin, g.point - w.center) - b.vel[p.end1]) * world.clock.dt;
        const double slide = step.dot(perp(g.normal));
        touch.closure =
            std::max(-step.dot(g.normal), 0.0) + slide * slide / (2.0 * b.radius[p.end1]);
    }
    touch.born_overlapped = g.overlap > touch.closure * (1.0 + 1e-9) + 1e-15;
    // The guard follows its first kGuardWatch steps (pass_finish.hpp, watchYoungContact).
    if (guard) {
        GuardWatch& w = world.contacts.startWatch(p, c);
        w.approach_rate = std::max(-vrel.dot(g.normal), 0.0);
        w.closure = touch.closure;
        w.born_overlapped = touch.born_overlapped;
    }
    if (world.callbacks.contact_events) noteContactCreated(world, p, c, g.point);
    return touch;
}

void noteContactCreated(World& world, const Pair& p, const PairCold& c, const Vec2& point) {
    Event ev;
    ev.kind = EventKind::ContactCreated;
    ev.time = world.clock.time;
    ev.pos = point;
    ev.contact = ContactKey{c.key};
    ev.model = world.contacts.ruleOf(p).model_name;
    world.callbacks.events.push_back(std::move(ev));
}

double notePlacement(World& world, const Pair& p, double closure, double overlap, const FdBlock& fd,
                     bool energy) {
    // The model's stored energy at its first call includes what the closure within this step
    // put in (activate); the rest was there before the step. Stored energy grows about as the
    // overlap squared (exactly so for a linear spring), so the part that was placed is the fraction
    // ((overlap - approach dt) / overlap)^2 of it. Without tracing, the linear estimate
    // knest overlap^2 / 2 names the size in the warning.
    const double before = std::max(overlap - closure, 0.0);
    const double share = overlap > 0.0 ? (before / overlap) * (before / overlap) : 0.0;
    const double stored = energy ? fd.energy[kEnergyStrain] + fd.energy[kEnergyBondStrain]
                                 : 0.5 * fd.knest * overlap * overlap;
    const double placed = share * stored;
    world.books.last_placed = placed;
    // Below a thousandth of the radius it is bookkeeping, not a user's placement (a contact
    // formed by a spin-driven slide, rounding). Booked, not reported.
    const auto& b = world.bodies.balls;
    const double r = p.wall ? b.radius[p.end1] : std::min(b.radius[p.end1], b.radius[p.end2]);
    // A routine that overlaps bodies on purpose says so itself (Model::setPlacementWarning).
    if (overlap < 1e-3 * r || !world.guard_state.placement_warning) return placed;
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

void noteDeepest(const World& world, const PairCold& c, GuardWatch& w, double force,
                 double rate_after) {
    if (c.overlap <= w.overlap_max) return;
    w.overlap_max = c.overlap;
    w.force_at_max = force;
    w.rate_at_max = rate_after;
    w.knest_at_max = c.knest;
    w.dt_at_max = world.clock.dt;
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
    // The model object still holds the bond's geometry here; by the time the event is
    // delivered a contact that ended in the breaking step has a fresh one.
    ev.radius = bondRadius(world.contacts, world.contacts.pairs[i]);
    ev.time = world.clock.time;
    ev.pos = point;
    ev.contact = ContactKey{world.contacts.cold[i].key};
    ev.mode = mode;
    ev.model = world.contacts.ruleOf(world.contacts.pairs[i]).model_name;
    if (with_stress) {
        ev.sigma = sigma;
        ev.tau = tau;
    }
    world.callbacks.events.push_back(std::move(ev));
}

namespace {

/// The guard's judgement of a contact at its end, from its watch (docs/physics/guard.md): the
/// energy it gave back, whether the step resolved it, whether its model reported its stiffness.
void judgeContact(World& world, const Pair& p, const PairCold& c, const GuardWatch& w) {
    // A contact created overlapping (by placement) gives back energy it never took.
    // Reference: the larger of the energy the contact held at its peak and the kinetic
    // energy of the approach (a contact that only ever gave energy has no peak).
    const double reference =
        std::max(w.work_peak, 0.5 * c.mass_eff * w.approach_rate * w.approach_rate);
    if (world.settings.guard.energy != GuardAction::Off && !w.born_overlapped && reference > 0.0 &&
        w.work < -world.settings.guard.energy_tolerance * reference) {
        const std::string what =
            describePair(world, p) + " returned " + num(-w.work) +
            " J more than it took (reference " + num(reference) + " J, tolerance " +
            num(100.0 * world.settings.guard.energy_tolerance) + "%) over " +
            std::to_string(w.steps) + " steps ending at t = " + num(world.clock.time) +
            " s; the step (" + num(world.clock.dt) +
            " s) is too large for the model's stiffness, or the "
            "model reports too low a stiffness (knest " +
            num(c.knest) + " N/m)";
        // Judged at the step's end against the scene's energy (bookkeeping.cpp,
        // judgeEnergyGains), when every contact of the step has its new force.
        world.guard_state.energy_gains.push_back({-w.work, what});
    }
    // Under-resolved: a step taken during the contact was too large for the impact's own
    // duration (the model's estimate at touch). A contact that is short for other reasons
    // (grazing, knocked away) is not a finding; a model that misreports its stiffness is the
    // stiffness check's business.
    if (world.settings.guard.resolution != GuardAction::Off && !p.bonded &&
        c.duration < world.settings.guard.min_steps * w.dt_at_max) {
        const std::string what = describePair(world, p) + " had " + num(c.duration / w.dt_at_max) +
                                 " steps per contact duration (" + num(c.duration) +
                                 " s at dt = " + num(w.dt_at_max) +
                                 " s, t = " + num(world.clock.time) + " s); it lasted " +
                                 std::to_string(w.steps) + " steps";
        // (fewer than severe_min_steps: no sound run does that; docs/physics/guard.md)
        const bool severe = world.settings.guard.severe == GuardAction::Error &&
                            c.duration < world.settings.guard.severe_min_steps * w.dt_at_max;
        if (world.settings.guard.resolution == GuardAction::Error || severe)
            throw NumericalError(
                "impact under-resolved: " + what + "; at least " +
                std::to_string(world.settings.guard.min_steps) + " steps are needed" +
                (severe ? severeNote("fewer than " +
                                     std::to_string(world.settings.guard.severe_min_steps) +
                                     " steps per contact duration, severe_min_steps")
                        : std::string()));
        if (world.guard_state.underresolved++ == 0) world.guard_state.underresolved_first = what;
    }
    // At the deepest overlap the force may be up to twice the reported stiffness times the
    // overlap (tangent vs secant), plus what a dashpot up to critical damping,
    // c = 2 sqrt(m knest), gives at the rate there: about zero for a resolved impact, the
    // rate just after the deepest overlap for a contact in a packing. A contact no deeper
    // than the closure of its first step (a graze, or an impact resolved in one step) may
    // have its deepest overlap at that first step, whose force was computed from the
    // approach rate, not the rate after, and carries what the model adds for a touch inside
    // the step: its dashpot over the window from touch, up to 1.5 steps' worth at the
    // approach rate, and the spring's onset corner, up to knest times an eighth of the
    // closure (talus/sdk/corners.hpp). In a settled pack such contacts touch at
    // micrometres per second for a step or two, their overlap a few nanometres, and those
    // terms are most of their force.
    const double secant = w.overlap_max > 0.0 ? w.force_at_max / w.overlap_max : 0.0;
    const double dashpot = 2.0 * std::sqrt(c.mass_eff * w.knest_at_max);
    const bool shallow = w.overlap_max <= w.closure * (1.0 + 1e-9) + 1e-15;
    const double allowed =
        shallow ? 2.0 * w.knest_at_max * (w.overlap_max + 0.125 * w.closure) +
                      dashpot * std::max(1.5 * w.approach_rate, std::fabs(w.rate_at_max))
                : 2.0 * w.knest_at_max * w.overlap_max + dashpot * std::fabs(w.rate_at_max);
    if (world.settings.guard.stiffness != GuardAction::Off && !p.bonded &&
        w.force_at_max > allowed) {
        const std::string what =
            describePair(world, p) + ": at its deepest overlap its normal force was " +
            num(secant) + " N/m of overlap while it reported knest " + num(w.knest_at_max) +
            " N/m; the time step follows knest, so the model must report its true tangent "
            "stiffness (docs/plugin-abi.md, time-step contract)";
        if (world.settings.guard.stiffness == GuardAction::Error)
            throw NumericalError("stiffness under-reported: " + what);
        if (world.guard_state.stiffness_lies++ == 0) world.guard_state.stiffness_lies_first = what;
    }
}

}  // namespace

void endContact(World& world, Pair& p, PairCold& c, bool check_guard) {
    const GuardWatch* w = world.contacts.watchOf(c);
    if (check_guard && w && w->steps > 0 && w->steps <= kGuardWatch) judgeContact(world, p, c, *w);
    resetPair(world, p);
}

}  // namespace talus
