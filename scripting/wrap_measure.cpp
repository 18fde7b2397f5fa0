// SPDX-License-Identifier: MIT
// m:measure{circle = {x, y, r} | box = {xmin, ymin, xmax, ymax}} and m:unbalanced()
// (core/src/api/measure.cpp; docs/lua-api.md "Measurement").
#include <cmath>
#include <string>

#include "lua_bindings.hpp"
#include "talus/errors.hpp"

namespace talus::lua {

namespace {

void pushTensor(lua_State* L, double xx, double yy, double xy) {
    lua_createtable(L, 0, 3);
    lua_pushnumber(L, xx);
    lua_setfield(L, -2, "xx");
    lua_pushnumber(L, yy);
    lua_setfield(L, -2, "yy");
    lua_pushnumber(L, xy);
    lua_setfield(L, -2, "xy");
}

int w_measure(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "measure");
        const Options o(L, 2, "measure", {"circle", "box"});
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
        lua_pushnumber(L, r.porosity);
        lua_setfield(L, -2, "porosity");
        lua_pushnumber(L, r.coordination);
        lua_setfield(L, -2, "coordination");
        pushTensor(L, r.stress_xx, r.stress_yy, r.stress_xy);
        lua_setfield(L, -2, "stress");
        pushTensor(L, r.rate_xx, r.rate_yy, r.rate_xy);
        lua_setfield(L, -2, "strain_rate");
        lua_pushnumber(L, r.rate_spin);
        lua_setfield(L, -2, "spin");
        lua_pushinteger(L, static_cast<lua_Integer>(r.balls));
        lua_setfield(L, -2, "balls");
        lua_pushinteger(L, static_cast<lua_Integer>(r.contacts));
        lua_setfield(L, -2, "contacts");
        lua_pushnumber(L, r.area);
        lua_setfield(L, -2, "area");
        lua_pushnumber(L, r.solid);
        lua_setfield(L, -2, "solid");
        return 1;
    });
}

int w_unbalanced(lua_State* L) {
    return catchexcept(L, [&] {
        LuaModel& lm = checkModel(L, 1, "unbalanced");
        const UnbalancedForce u = lm.model->unbalanced();
        lua_createtable(L, 0, 6);
        lua_pushnumber(L, u.mean_unbalanced);
        lua_setfield(L, -2, "mean_unbalanced");
        lua_pushnumber(L, u.max_unbalanced);
        lua_setfield(L, -2, "max_unbalanced");
        lua_pushnumber(L, u.mean_contact);
        lua_setfield(L, -2, "mean_contact");
        lua_pushnumber(L, u.ratio);
        lua_setfield(L, -2, "ratio");
        lua_pushinteger(L, static_cast<lua_Integer>(u.bodies));
        lua_setfield(L, -2, "bodies");
        lua_pushinteger(L, static_cast<lua_Integer>(u.contacts));
        lua_setfield(L, -2, "contacts");
        return 1;
    });
}

}  // namespace

extern const luaL_Reg kMeasureMethods[] = {
    {"measure", w_measure},
    {"unbalanced", w_unbalanced},
    {nullptr, nullptr},
};

}  // namespace talus::lua
