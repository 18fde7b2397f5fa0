// SPDX-License-Identifier: MIT
//
// Broadphase: Box2D's b2DynamicTree holding one fat box per ball and per wall segment.
//
// The tree works in single precision and pads every box by a fixed b2_aabbExtension (0.1 of its
// own units). We give it scaled coordinates, tree = world * scale with scale = 0.1 / margin, so
// that its padding is exactly `margin` world units whatever the size of the model; boxes are
// rounded outward when converted to float so a fat box always contains the true box.
// Callers pass the body's box already grown by `margin`; the fat box is then the body's box
// grown by 2 margins, and the body is re-inserted when it has less than one margin of room left.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "talus/vec.hpp"

namespace talus {
class SaveWriter;
class SaveReader;
}  // namespace talus

namespace talus {

class Broadphase {
public:
    Broadphase();
    ~Broadphase();

    /// Clears the tree and sets the padding [m].
    void reset(double margin);
    double margin() const { return m_margin; }

    int32_t create(const Box& box, uint32_t user);
    void destroy(int32_t proxy);
    /// Re-inserts the proxy if `box` is no longer inside its fat box; returns true if it did.
    bool move(int32_t proxy, const Box& box);
    /// The fat box in world units (rounded outward).
    Box fatBox(int32_t proxy) const;
    uint32_t user(int32_t proxy) const;
    /// Appends the proxies whose fat boxes overlap `box` (in tree order).
    void query(const Box& box, std::vector<int32_t>& out) const;

    /// Saves the tree node for node (docs/save-format.md): a restored tree answers queries in
    /// the same order, so contacts are created in the same order and a continued run stays
    /// bit-identical.
    void save(SaveWriter& w) const;
    /// Restores a tree written by save(), checking its structure (every node in range, reached
    /// once, heights and the free list consistent); throws InputError through `r` otherwise.
    void restore(SaveReader& r);
    /// Why save() and restore() cannot run with the Box2D this process uses (they mirror the
    /// private node array of Box2D 2.4's tree), or empty.
    static std::string treeLayoutProblem();
    /// True when `proxy` is a leaf of the tree (a body's proxy).
    bool isLeaf(int32_t proxy) const;
    /// Number of leaves (bodies) in the tree.
    std::size_t leafCount() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    double m_margin = 0.0;
};

}  // namespace talus
