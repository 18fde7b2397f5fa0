// SPDX-License-Identifier: MIT
//
// Cracks: a broken bond seen as PFC's crack.fis sees it, a line segment at the contact point
// across the bond (docs/lua-api.md "Cracks"). The bond_break events of a model are kept as
// cracks by the Lua layer (LuaModel::cracks); m:cracks() lists them, M.compress / M.brazilian
// write them, and m:picture / m:vtk draw them. Lua-free, so the writers take them as they are.
#pragma once

#include <cstdint>

#include "talus/model.hpp"

namespace talus {

struct Crack {
    double time = 0.0;      ///< when the bond broke [s]
    int64_t step = 0;       ///< the model's step count when the event was delivered (m:step())
    Vec2 pos{0.0, 0.0};     ///< the contact point
    Vec2 normal{0.0, 0.0};  ///< unit normal of the bond, from ball 1 toward ball 2 (or the wall)
    double radius = 0.0;    ///< the bond's half width [m]: the crack runs +-radius across it
    int32_t mode = 0;       ///< BreakMode: kBreakTension or kBreakShear
    BallId ball1;           ///< the bond's ends (ball2 invalid for a bond to a wall)
    BallId ball2;
    double sigma = 0.0;  ///< peak normal / shear stress at failure [Pa] when the model
    double tau = 0.0;    ///< reports them (pbond), NaN otherwise

    /// The crack's end points: the segment through pos perpendicular to the normal.
    Vec2 end1() const { return pos + radius * Vec2(-normal.y(), normal.x()); }
    Vec2 end2() const { return pos - radius * Vec2(-normal.y(), normal.x()); }
};

/// The crack of a bond_break event, read from the model when the event is delivered (after the
/// step's force loop; the contact still exists then). The bond's radius is the event's, which
/// the engine read from the model as the bond broke (Event::radius: `pb_rad` of a parallel
/// bond, Potyondy & Cundall 2004; `fj_radius` of a flat joint), else the smaller ball's radius
/// (a contact bond has no size of its own); the normal is the line of the ball centres (for a
/// wall: the contact's normal). If the contact is gone the crack has the event's point, time
/// and mode only (radius 0, no ends).
Crack crackOf(Model& m, const Event& ev);

}  // namespace talus
