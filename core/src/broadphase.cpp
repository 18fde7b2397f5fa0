// SPDX-License-Identifier: MIT
#include "broadphase.hpp"

#include <box2d/b2_dynamic_tree.h>

#include <cmath>
#include <cstdint>

namespace talus {

namespace {

// Tree padding in tree units, as compiled into Box2D (b2_aabbExtension).
constexpr double kTreeExtension = 0.1;

float down(double v) {
    float f = static_cast<float>(v);
    return static_cast<double>(f) > v ? std::nextafter(f, -INFINITY) : f;
}
float up(double v) {
    float f = static_cast<float>(v);
    return static_cast<double>(f) < v ? std::nextafter(f, INFINITY) : f;
}

}  // namespace

struct Broadphase::Impl {
    b2DynamicTree tree;
    double scale = 1.0;

    b2AABB toTree(const Box& b) const {
        b2AABB a;
        a.lowerBound.Set(down(b.lo.x() * scale), down(b.lo.y() * scale));
        a.upperBound.Set(up(b.hi.x() * scale), up(b.hi.y() * scale));
        return a;
    }
    Box toWorld(const b2AABB& a) const {
        // Dividing may round inward by one ulp; shrink-safe because the fat box only decides
        // candidates, and the room test keeps a full margin in reserve.
        Box b;
        b.lo = Vec2(a.lowerBound.x / scale, a.lowerBound.y / scale);
        b.hi = Vec2(a.upperBound.x / scale, a.upperBound.y / scale);
        return b;
    }
};

Broadphase::Broadphase() : m_impl(std::make_unique<Impl>()) {}
Broadphase::~Broadphase() = default;

void Broadphase::reset(double margin) {
    m_impl = std::make_unique<Impl>();
    m_margin = margin;
    m_impl->scale = kTreeExtension / margin;
}

int32_t Broadphase::create(const Box& box, uint32_t user) {
    return m_impl->tree.CreateProxy(m_impl->toTree(box),
                                    reinterpret_cast<void*>(static_cast<uintptr_t>(user)));
}

void Broadphase::destroy(int32_t proxy) { m_impl->tree.DestroyProxy(proxy); }

bool Broadphase::move(int32_t proxy, const Box& box) {
    return m_impl->tree.MoveProxy(proxy, m_impl->toTree(box), b2Vec2(0.0f, 0.0f));
}

Box Broadphase::fatBox(int32_t proxy) const {
    return m_impl->toWorld(m_impl->tree.GetFatAABB(proxy));
}

uint32_t Broadphase::user(int32_t proxy) const {
    return static_cast<uint32_t>(reinterpret_cast<uintptr_t>(m_impl->tree.GetUserData(proxy)));
}

void Broadphase::query(const Box& box, std::vector<int32_t>& out) const {
    struct Collector {
        std::vector<int32_t>* out;
        bool QueryCallback(int32_t id) {
            out->push_back(id);
            return true;
        }
    } c{&out};
    m_impl->tree.Query(&c, m_impl->toTree(box));
}

}  // namespace talus
