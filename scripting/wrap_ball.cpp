// SPDX-License-Identifier: MIT
// Ball userdata: an id and its model. Fields read and write the engine state by id, so a
// ball deleted in the meantime gives the engine's "ball 3 was deleted (stale id)".
#include "field_accessors.hpp"
#include "lua_bindings.hpp"

namespace talus::lua {

namespace {

using namespace fields;
using B = BallRef;

const Field kBallFields[] = {
    {"id", "integer", "the ball's handle number (1, 2, ...)", getIndex<B, &Model::ballRadius>},
    {"pos", "talus.Vec", "centre [m]", get<B, &Model::ballPos>, set<B, &Model::setBallPos>},
    {"vel", "talus.Vec", "velocity at the half step t - dt/2 [m/s]", get<B, &Model::ballVel>,
     set<B, &Model::setBallVel>},
    {"spin", "number", "angular velocity at the half step [rad/s], counter-clockwise positive",
     get<B, &Model::ballSpin>, set<B, &Model::setBallSpin>},
    {"angle", "number", "orientation [rad]", get<B, &Model::ballAngle>},
    {"radius", "number", "[m]; writing it updates mass and inertia when the ball has a density",
     get<B, &Model::ballRadius>, set<B, &Model::setBallRadius>},
    {"mass", "number", "[kg]", get<B, &Model::ballMass>},
    {"inertia", "number", "moment of inertia [kg m^2]", get<B, &Model::ballInertia>},
    {"density", "number", "[kg/m^3]; writing it updates mass and inertia",
     get<B, &Model::ballDensity>, set<B, &Model::setBallDensity>},
    {"force", "talus.Vec", "sum of the contact forces of the last step [N]",
     get<B, &Model::ballForce>},
    {"moment", "number", "sum of the contact moments of the last step [N m]",
     get<B, &Model::ballMoment>},
    {"fapp", "talus.Vec", "applied force [N], kept until changed", get<B, &Model::ballAppliedForce>,
     set<B, &Model::setBallAppliedForce>},
    {"mapp", "number", "applied moment [N m], kept until changed",
     get<B, &Model::ballAppliedMoment>, set<B, &Model::setBallAppliedMoment>},
    {"groups", "string[]", "the ball's group names", get<B, &Model::ballGroups>},
    {"fix", "string[]|boolean", "fixed velocity components, {\"x\", \"y\", \"spin\"}; true all",
     getFixity<B, &Model::ballFixity>, setFixity<B, &Model::setBallFixity>},
    {"kn", "number?", "own normal stiffness [N/m], inherited by its contacts; nil: not set",
     getProp<B, &Model::ballContactProp, kKn>, setProp<B, &Model::setBallContactProp, kKn>},
    {"ks", "number?", "own shear stiffness [N/m], inherited by its contacts; nil: not set",
     getProp<B, &Model::ballContactProp, kKs>, setProp<B, &Model::setBallContactProp, kKs>},
    {"fric", "number?", "own friction coefficient, inherited by its contacts; nil: not set",
     getProp<B, &Model::ballContactProp, kFric>, setProp<B, &Model::setBallContactProp, kFric>},
    {"alive", "boolean", "false once the ball was deleted (never an error)", getAlive<B>},
};

constexpr char kWhat[] = "ball";

const Method kBallMethods[] = {
    {"set", objectSet, "writes several fields at once, in sorted name order",
     "fields: talus.BallFields", ""},
    {"delete", actMethod<B, &Model::deleteBall, kDelete>, "removes the ball and its contacts", "",
     ""},
    {"add_group", addGroup<B, &Model::addBallGroup>, "adds the ball to a group", "name: string",
     ""},
};

const ObjectType kBallObject = {
    kBallType,
    kWhat,
    "b",
    "a ball: fields read and write the engine's state by id",
    kBallFields,
    kBallMethods,
    describeBody<B, &Model::ballPos, kWhat>,
};

const ObjectType* const kTypes[] = {&kBallObject};

}  // namespace

extern const Binding kBallBinding = {"ball", {}, {}, kTypes, {}, {}};

BallRef* testBall(lua_State* L, int index) {
    return static_cast<BallRef*>(testUserdata(L, index, kBallType));
}

void pushBall(lua_State* L, int model_index, BallId id) {
    newObject<BallRef>(L, model_index, kBallObject)->id = id;
}

}  // namespace talus::lua
