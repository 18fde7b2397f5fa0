// SPDX-License-Identifier: MIT
// talus.impact{...} and talus.drive{...}: the single-contact rig (core impact_rig.hpp).
// Angles cross the boundary in degrees (users think of impact angles in degrees); everything
// else is SI, as in the engine.
#include <cmath>

#include "lua_bindings.hpp"
#include "talus/impact_rig.hpp"
#include "talus/plugin_registry.hpp"

namespace talus::lua {

namespace {

constexpr double kDegree = M_PI / 180.0;

void pushNumbers(lua_State* L, const std::vector<double>& v) {
    lua_createtable(L, static_cast<int>(v.size()), 0);
    for (std::size_t i = 0; i < v.size(); ++i) {
        lua_pushnumber(L, v[i]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
}

/// Pushes the columns of a trace: {time = {...}, overlap = {...}, ...}.
void pushTrace(lua_State* L, const std::vector<TracePoint>& trace) {
    std::vector<double> t, u, fn, fs, mo;
    for (const TracePoint& p : trace) {
        t.push_back(p.time);
        u.push_back(p.overlap);
        fn.push_back(p.normal_force);
        fs.push_back(p.shear_force);
        mo.push_back(p.moment);
    }
    lua_createtable(L, 0, 5);
    pushNumbers(L, t);
    lua_setfield(L, -2, "time");
    pushNumbers(L, u);
    lua_setfield(L, -2, "overlap");
    pushNumbers(L, fn);
    lua_setfield(L, -2, "normal_force");
    pushNumbers(L, fs);
    lua_setfield(L, -2, "shear_force");
    pushNumbers(L, mo);
    lua_setfield(L, -2, "moment");
}

std::vector<PropValue> propsOption(const Options& o, const std::string& model) {
    if (o.push("props") == LUA_TNIL) {
        lua_pop(o.state(), 1);
        return {};
    }
    std::vector<PropValue> props = readProps(o.state(), -1, model, o.what());
    const ContactModel* meta = PluginRegistry::global().find(model).reference;
    std::vector<std::pair<std::string, double>> fric;
    for (const PropValue& p : props)
        if (isFrictionCoefficient(p.name, meta)) fric.emplace_back(p.name, p.value);
    warnImplausibleFriction(nullptr, o.what(), fric);
    lua_pop(o.state(), 1);
    return props;
}

const Option kImpactOptionRows[] = {
    {"model", "string", "the contact model (default \"linear\")"},
    {"props", "table<string, number|string>", "its properties, as in m:contact_model"},
    {"target", "\"wall\"|\"ball\"", "a horizontal wall (default) or a ball"},
    {"radius", "number", "the impactor's radius [m] (default 0.1)"},
    {"density", "number", "the impactor's density [kg/m^3] (default 2600)"},
    {"target_radius", "number", "the target ball's radius [m] (default 0.1)"},
    {"target_density", "number", "the target ball's density [kg/m^3] (default 2600)"},
    {"mass", "\"disk\"|\"sphere\"", "the mass mode (default disk)"},
    {"speed", "number", "normal approach speed [m/s] (default 1)"},
    {"tangential", "number", "tangential velocity [m/s] (default 0)"},
    {"angle", "number", "with velocity: degrees from the normal, in [0, 90)"},
    {"velocity", "number", "with angle: the impact speed [m/s]"},
    {"spin", "number", "the impactor's spin [rad/s] (default 0)"},
    {"target_speed", "number", "the target ball's velocity toward the impactor [m/s]"},
    {"target_spin", "number", "the target ball's spin [rad/s]"},
    {"gap", "number", "initial gap [m] (default 1e-3 R)"},
    {"timestep", "talus.TimestepOptions", "as m:timestep{...}"},
    {"guard", "talus.GuardOptions", "as m:guard{...}"},
    {"trace", "string|boolean", "a CSV file of the trace, or true: result.trace"},
    {"max_steps", "integer", "the most steps (default 1e7)"},
};
const OptionTable kImpactOptions = {"talus.ImpactOptions",
                                    "talus.impact{...}: one impact on the single-contact rig",
                                    kImpactOptionRows};

const Option kDriveOptionRows[] = {
    {"model", "string", "the contact model (default \"linear\")"},
    {"props", "table<string, number|string>", "its properties, as in m:contact_model"},
    {"target", "\"wall\"|\"ball\"", "a wall (default) or a ball"},
    {"radius", "number", "[m] (default 0.1)"},
    {"target_radius", "number", "[m] (default 0.1)"},
    {"mass", "number", "[kg] (default 1)"},
    {"target_mass", "number", "[kg] (default 1)"},
    {"dt", "number", "time between samples [s] (default 1e-6)"},
    {"overlap", "number[]", "the overlaps u_n [m], one per sample", true},
    {"shear", "number[]", "shear displacements [m], as many as overlap"},
};
const OptionTable kDriveOptions = {"talus.DriveOptions",
                                   "talus.drive{...}: a contact driven through an overlap history",
                                   kDriveOptionRows};

/// The impact's velocities: speed and tangential, or velocity at an angle from the normal.
void readVelocities(const Options& o, ImpactSetup& s) {
    if (o.has("angle") || o.has("velocity")) {
        if (o.has("speed") || o.has("tangential"))
            throw ScriptError("impact: give either speed/tangential or velocity/angle");
        if (!o.has("angle") || !o.has("velocity"))
            throw ScriptError(
                "impact: 'angle' (degrees from the normal) and 'velocity' (impact speed) go "
                "together");
        const double v = o.number("velocity", 0.0);
        const double a = o.number("angle", 0.0);
        if (!(a >= 0.0 && a < 90.0))
            throw ScriptError("impact: 'angle' must be in [0, 90) degrees from the normal (got " +
                              numberText(a) + ")");
        s.normal_speed = v * std::cos(a * kDegree);
        s.tangential_speed = v * std::sin(a * kDegree);
    } else {
        s.normal_speed = o.number("speed", s.normal_speed);
        s.tangential_speed = o.number("tangential", s.tangential_speed);
    }
    s.spin = o.number("spin", s.spin);
    s.target_speed = o.number("target_speed", s.target_speed);
    s.target_spin = o.number("target_spin", s.target_spin);
}

/// The run's controls: time step, guard and the step cap.
void readControls(const Options& o, ImpactSetup& s) {
    lua_State* L = o.state();
    s.gap = o.number("gap", s.gap);
    s.max_steps = o.integer("max_steps", s.max_steps);
    if (s.max_steps < 1) throw ScriptError("impact: 'max_steps' must be >= 1");
    if (o.push("timestep") != LUA_TNIL) {
        const Options ts(L, -1, "timestep", kTimestepOptions);
        readTimestepOptions(ts, s.timestep);
    }
    lua_pop(L, 1);
    if (o.push("guard") != LUA_TNIL) {
        const Options g(L, -1, "guard", kGuardOptions);
        readGuardOptions(g, s.guard);
    }
    lua_pop(L, 1);
}

/// trace = "file.csv" | true: where the trace goes ("" and false: nowhere).
void readTrace(const Options& o, std::string& file, bool& table) {
    lua_State* L = o.state();
    const int t = o.push("trace");
    if (t == LUA_TSTRING) file = lua_tostring(L, -1);
    table = t == LUA_TBOOLEAN && lua_toboolean(L, -1);
    lua_pop(L, 1);
    if (t != LUA_TNIL && t != LUA_TSTRING && t != LUA_TBOOLEAN)
        throw ScriptError("impact: 'trace' must be a CSV file name or true");
}

void pushImpactResult(lua_State* L, const ImpactResult& r) {
    lua_createtable(L, 0, 28);
    setBoolean(L, "separated", r.separated);
    setNumber(L, "restitution", r.restitution);
    setNumber(L, "tangential_restitution", r.tangential_restitution);
    setNumber(L, "vn_in", r.vn_in);
    setNumber(L, "vn_out", r.vn_out);
    setNumber(L, "vt_in", r.vt_in);
    setNumber(L, "vt_out", r.vt_out);
    setNumber(L, "slip_in", r.slip_in);
    setNumber(L, "slip_out", r.slip_out);
    setNumber(L, "spin_out", r.spin_out);
    setNumber(L, "target_spin_out", r.target_spin_out);
    setNumber(L, "rebound_angle", r.rebound_angle / kDegree);
    setNumber(L, "contact_point_angle", r.contact_point_angle / kDegree);
    setNumber(L, "duration", r.duration);
    setNumber(L, "force_duration", r.force_duration);
    setNumber(L, "peak_force", r.peak_force);
    setNumber(L, "max_overlap", r.max_overlap);
    setInteger(L, "steps", static_cast<lua_Integer>(r.steps_in_contact));
    setNumber(L, "timestep", r.timestep);
    setString(L, "step_rule", r.step_rule);
    setNumber(L, "energy_in", r.energy_in);
    setNumber(L, "energy_out", r.energy_out);
    pushEnergies(L, r.energy);
    lua_setfield(L, -2, "energies");
}

int w_impact(lua_State* L) {
    return catchexcept(L, [&] {
        const Options o(L, 1, "impact", kImpactOptions);
        ImpactSetup s;
        s.model = o.string("model", s.model);
        s.props = propsOption(o, s.model);
        s.ball_target = o.choice("target", 0, {"wall", "ball"}) == 1;
        s.mass_mode =
            o.choice("mass", 0, {"disk", "sphere"}) == 0 ? MassMode::Disk : MassMode::Sphere;
        s.radius = o.number("radius", s.radius);
        s.density = o.number("density", s.density);
        s.target_radius = o.number("target_radius", s.target_radius);
        s.target_density = o.number("target_density", s.target_density);
        readVelocities(o, s);
        readControls(o, s);
        std::string trace_file;
        bool trace_table = false;
        readTrace(o, trace_file, trace_table);
        s.keep_trace = !trace_file.empty() || trace_table;

        const ImpactResult r = runImpact(s);
        if (!trace_file.empty()) writeTraceCsv(r.trace, trace_file);
        pushImpactResult(L, r);
        if (trace_table) {
            pushTrace(L, r.trace);
            lua_setfield(L, -2, "trace");
        }
        return 1;
    });
}

int w_drive(lua_State* L) {
    return catchexcept(L, [&] {
        const Options o(L, 1, "drive", kDriveOptions);
        DriveSetup s;
        s.model = o.string("model", s.model);
        s.props = propsOption(o, s.model);
        s.ball_target = o.choice("target", 0, {"wall", "ball"}) == 1;
        s.radius = o.number("radius", s.radius);
        s.target_radius = o.number("target_radius", s.target_radius);
        s.mass = o.number("mass", s.mass);
        s.target_mass = o.number("target_mass", s.target_mass);
        s.dt = o.number("dt", s.dt);
        s.overlap = o.numbers("overlap");
        s.shear = o.numbers("shear");
        if (s.overlap.empty())
            throw ScriptError("drive: 'overlap' (a list of overlaps [m]) is required");
        if (!(s.radius > 0.0) || !(s.mass > 0.0))
            throw ScriptError("drive: 'radius' and 'mass' must be > 0");
        if (s.ball_target && (!(s.target_radius > 0.0) || !(s.target_mass > 0.0)))
            throw ScriptError("drive: 'target_radius' and 'target_mass' must be > 0");

        const DriveResult r = driveContact(s);
        pushTrace(L, r.trace);
        pushNumbers(L, r.knest);
        lua_setfield(L, -2, "knest");
        setNumber(L, "strain", r.strain);
        setNumber(L, "slip", r.slip);
        setNumber(L, "dashpot", r.dashpot);
        setNumber(L, "plastic", r.plastic);
        return 1;
    });
}

const Method kImpactFunctions[] = {
    {"impact", w_impact, "one impact on the single-contact rig, run to separation",
     "options: talus.ImpactOptions", "table"},
    {"drive", w_drive, "a fresh contact driven through a prescribed overlap (and shear) history",
     "options: talus.DriveOptions", "table"},
};

const OptionTable* const kOptionTables[] = {&kImpactOptions, &kDriveOptions};

}  // namespace

extern const Binding kImpactBinding = {"impact rig", {}, kImpactFunctions, {}, kOptionTables, {}};

}  // namespace talus::lua
