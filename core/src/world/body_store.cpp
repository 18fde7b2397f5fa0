// SPDX-License-Identifier: MIT
// The body store (body_store.hpp): ball arrays and the handle tables.
#include "world/body_store.hpp"

#include <string>

#include "talus/errors.hpp"
#include "world/capacity.hpp"
#include "world/messages.hpp"

namespace talus {

void BallArrays::resize(std::size_t n) {
    pos.resize(n), vel.resize(n), force.resize(n), fapp.resize(n);
    angle.resize(n), spin.resize(n), moment.resize(n), mapp.resize(n);
    radius.resize(n), mass.resize(n), inv_mass.resize(n), inertia.resize(n), inv_inertia.resize(n),
        density.resize(n);
    fixity.resize(n), handle.resize(n), proxy.resize(n), fat.resize(n), groups.resize(n);
    kn.resize(n), ks.resize(n), fric.resize(n), k_tran.resize(n), k_rot.resize(n);
    clump.resize(n, kNoClump);
}

void BallArrays::trim() {
    auto trim = [](auto& v) { trimCapacity(v); };
    trim(pos), trim(vel), trim(force), trim(fapp), trim(angle), trim(spin), trim(moment);
    trim(mapp), trim(radius), trim(mass), trim(inv_mass), trim(inertia), trim(inv_inertia);
    trim(density), trim(fixity), trim(handle), trim(proxy), trim(fat), trim(groups);
    trim(kn), trim(ks), trim(fric), trim(k_tran), trim(k_rot), trim(clump);
}

void BallArrays::move(std::size_t to, std::size_t from) {
    pos[to] = pos[from], vel[to] = vel[from], force[to] = force[from], fapp[to] = fapp[from];
    angle[to] = angle[from], spin[to] = spin[from], moment[to] = moment[from],
    mapp[to] = mapp[from];
    radius[to] = radius[from], mass[to] = mass[from], inv_mass[to] = inv_mass[from];
    inertia[to] = inertia[from], inv_inertia[to] = inv_inertia[from], density[to] = density[from];
    fixity[to] = fixity[from], handle[to] = handle[from], proxy[to] = proxy[from];
    fat[to] = fat[from], groups[to] = groups[from];
    kn[to] = kn[from], ks[to] = ks[from], fric[to] = fric[from];
    k_tran[to] = k_tran[from], k_rot[to] = k_rot[from], clump[to] = clump[from];
}

void BallArrays::permute(const std::vector<uint32_t>& new_to_old) {
    auto apply = [&](auto& v) {
        auto old = v;
        for (std::size_t i = 0; i < new_to_old.size(); ++i) v[i] = old[new_to_old[i]];
    };
    apply(pos), apply(vel), apply(force), apply(fapp), apply(angle), apply(spin), apply(moment);
    apply(mapp), apply(radius), apply(mass), apply(inv_mass), apply(inertia), apply(inv_inertia);
    apply(density), apply(fixity), apply(handle), apply(proxy), apply(fat), apply(groups);
    apply(kn), apply(ks), apply(fric), apply(k_tran), apply(k_rot), apply(clump);
}

uint32_t BodyStore::slotOf(BallId id) const {
    if (id.index == 0 || id.index > slot_of.size())
        throw InputError("ball id " + std::to_string(id.index) + " does not exist");
    const uint32_t slot = slot_of[id.index - 1];
    if (slot == kDeadSlot || generation[id.index - 1] != id.generation)
        throw InputError("ball " + std::to_string(id.index) + " was deleted (stale id)");
    return slot;
}

bool BodyStore::isAlive(BallId id) const {
    return id.index != 0 && id.index <= slot_of.size() && slot_of[id.index - 1] != kDeadSlot &&
           generation[id.index - 1] == id.generation;
}

std::string BodyStore::describeBall(uint32_t slot) const {
    return "ball " + std::to_string(balls.handle[slot]) + " at " + vecText(balls.pos[slot]);
}

uint32_t BodyStore::clumpIndex(ClumpId id) const {
    if (id.index == 0 || id.index > clumps.size())
        throw InputError("clump id " + std::to_string(id.index) + " does not exist");
    const ClumpData& c = clumps[id.index - 1];
    if (!c.alive || c.generation != id.generation)
        throw InputError("clump " + std::to_string(id.index) + " was deleted (stale id)");
    return id.index - 1;
}

const WallData& BodyStore::wallOf(WallId id) const {
    if (id.index == 0 || id.index > walls.size() || !walls[id.index - 1].alive ||
        walls[id.index - 1].generation != id.generation)
        throw InputError("wall id " + std::to_string(id.index) + " does not exist");
    return walls[id.index - 1];
}
WallData& BodyStore::wallOf(WallId id) {
    return const_cast<WallData&>(static_cast<const BodyStore*>(this)->wallOf(id));
}

}  // namespace talus
