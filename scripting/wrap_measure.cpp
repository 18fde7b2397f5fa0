// SPDX-License-Identifier: MIT
// m:measure{circle = {x, y, r} | box = {xmin, ymin, xmax, ymax}} and m:unbalanced()
// (core/src/measure.cpp; docs/lua-api.md "Measurement").
#include <cmath>
#include <string>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

namespace {

const Option kMeasureOptionRows[] = {
    {"circle", "number[]", "the region {x, y, radius} [m] (or box)"},
    {"box", "number[]", "the region {xmin, ymin, xmax, ymax} [m] (or circle)"},
};
const OptionTable kMeasureOptions = {
    "talus.MeasureOptions", "m:measure{...}: one region, circle or box", kMeasureOptionRows};

void pushTensor(lua_State* L, double xx, double yy, double xy) {
    lua_createtable(L, 0, 3);
    setNumber(L, "xx", xx);
    setNumber(L, "yy", yy);
    setNumber(L, "xy", xy);
}

int w_measure(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "measure");
        const Options o(L, 2, "measure", kMeasureOptions);
        if (o.has("circle") == o.has("box"))
            throw ScriptError(
                "measure: give one region, circle = {x, y, radius} or box = {xmin, "
                "ymin, xmax, ymax}");
        MeasureRegion rg;
        if (o.has("circle")) {
            const std::vector<double> v = o.numbers("circle");
            if (v.size() != 3)
                throw ScriptError("measure: circle = {x, y, radius} takes 3 numbers (got " +
                                  std::to_string(v.size()) + ")");
            rg.circle = true;
            rg.center = Vec2(v[0], v[1]);
            rg.radius = v[2];
        } else {
            const std::vector<double> v = o.numbers("box");
            if (v.size() != 4)
                throw ScriptError("measure: box = {xmin, ymin, xmax, ymax} takes 4 numbers (got " +
                                  std::to_string(v.size()) + ")");
            rg.circle = false;
            rg.lo = Vec2(v[0], v[1]);
            rg.hi = Vec2(v[2], v[3]);
        }
        const MeasureResult r = lm.model->measure(rg);
        lua_createtable(L, 0, 10);
        setNumber(L, "porosity", r.porosity);
        setNumber(L, "coordination", r.coordination);
        pushTensor(L, r.stress_xx, r.stress_yy, r.stress_xy);
        lua_setfield(L, -2, "stress");
        pushTensor(L, r.rate_xx, r.rate_yy, r.rate_xy);
        lua_setfield(L, -2, "strain_rate");
        setNumber(L, "spin", r.rate_spin);
        setInteger(L, "balls", static_cast<lua_Integer>(r.balls));
        setInteger(L, "contacts", static_cast<lua_Integer>(r.contacts));
        setNumber(L, "area", r.area);
        setNumber(L, "solid", r.solid);
        return 1;
    });
}

int w_unbalanced(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "unbalanced");
        const UnbalancedForce u = lm.model->unbalanced();
        lua_createtable(L, 0, 6);
        setNumber(L, "mean_unbalanced", u.mean_unbalanced);
        setNumber(L, "max_unbalanced", u.max_unbalanced);
        setNumber(L, "mean_contact", u.mean_contact);
        setNumber(L, "ratio", u.ratio);
        setInteger(L, "bodies", static_cast<lua_Integer>(u.bodies));
        setInteger(L, "contacts", static_cast<lua_Integer>(u.contacts));
        return 1;
    });
}

const Method kMeasureMethods[] = {
    {"measure", w_measure,
     "porosity, coordination, stress and strain rate in a region (PFC measurement circles)",
     "region: talus.MeasureOptions", "table"},
    {"unbalanced", w_unbalanced,
     "PFC's mechanical ratio: mean unbalanced force over mean contact force", "", "table"},
};

const OptionTable* const kOptionTables[] = {&kMeasureOptions};

}  // namespace

extern const Binding kMeasureBinding = {"measurement", kMeasureMethods, {}, {}, kOptionTables, {}};

}  // namespace talus::lua
