// SPDX-License-Identifier: MIT
#include "world/broadphase.hpp"

#include <box2d/b2_dynamic_tree.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "talus/errors.hpp"
#include "talus/save_file.hpp"

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

// Save and restore need the tree's node array, which b2DynamicTree keeps private and has no API
// for. An explicit instantiation may name private members (C++17 [temp.explicit]/14), so a
// template instantiated with pointers to them hands those pointers out through a friend.
//
// Why not save only what defines the tree (each proxy's fat box and body) and rebuild it on
// restore through the public API? Because the tree is not defined by its leaves: its shape is
// the history of its insertions, removals and rotations (InsertLeaf's cost heuristic, Balance),
// and the public API (CreateProxy, DestroyProxy, MoveProxy, RebuildBottomUp, ShiftOrigin) can
// make a tree of the same leaves but not that one. The shape decides the order of a query's
// hits, hence the order in which new pairs are made, hence the order of every force sum and the
// last bits of every result: a rebuilt tree continues a run correctly, but not bit for bit. The
// other ways cost more than this trick (docs/results/broadphase-save.md has the measurements):
//  - hits sorted by body before pairs are made (then a rebuilt tree gives the same pairs):
//    every result's last bits change once, everywhere (the stress digest; 6 of the 7 scenes of
//    tests/scripting/save_restore/ end in other states), and every query pays a sort;
//  - a log of the tree's operations since its last rebuild, replayed on restore: the tree is a
//    function of that log, but the log grows with every proxy move for as long as the run
//    lasts (a rockfall moves proxies at every step), in every run, saved or not;
//  - a tree of our own: its shape rules are not Box2D's, so the hit order and the results' last
//    bits change once as with the sort, and the save files written so far need a converter
//    (docs/architecture.md, "Box2D's tree in a save file": the moment for it is a new Box2D).
// So the trick stays, confined to this file and checked. It ties save files to Box2D 2.4's tree
// (Debian's libbox2d-dev 2.4.1; docs/save-format.md, "Box2D's tree"), the only
// broadphase Talus uses: the member pointers below must have exactly these types (a renamed or
// retyped member does not compile), the node must have the fields and the size saved below,
// and at run time the library must say it is 2.4 (Broadphase::save/restore refuse otherwise;
// test core.save_restore "Box2D's tree").
static_assert(sizeof(b2TreeNode) == 48 && offsetof(b2TreeNode, aabb) == 0 &&
                  offsetof(b2TreeNode, userData) == 16 && offsetof(b2TreeNode, parent) == 24 &&
                  offsetof(b2TreeNode, child1) == 28 && offsetof(b2TreeNode, child2) == 32 &&
                  offsetof(b2TreeNode, height) == 36 && offsetof(b2TreeNode, moved) == 40,
              "b2TreeNode is not Box2D 2.4.1's: the broadphase's save and restore (this file) "
              "must be checked against the new Box2D");
struct RootTag {
    using type = int32 b2DynamicTree::*;
};
struct NodesTag {
    using type = b2TreeNode* b2DynamicTree::*;
};
struct CountTag {
    using type = int32 b2DynamicTree::*;
};
struct CapacityTag {
    using type = int32 b2DynamicTree::*;
};
struct FreeTag {
    using type = int32 b2DynamicTree::*;
};
struct InsertTag {
    using type = int32 b2DynamicTree::*;
};
RootTag::type member(RootTag);
NodesTag::type member(NodesTag);
CountTag::type member(CountTag);
CapacityTag::type member(CapacityTag);
FreeTag::type member(FreeTag);
InsertTag::type member(InsertTag);
template <class Tag, typename Tag::type M>
struct Expose {
    friend typename Tag::type member(Tag) { return M; }
};
template struct Expose<RootTag, &b2DynamicTree::m_root>;
template struct Expose<NodesTag, &b2DynamicTree::m_nodes>;
template struct Expose<CountTag, &b2DynamicTree::m_nodeCount>;
template struct Expose<CapacityTag, &b2DynamicTree::m_nodeCapacity>;
template struct Expose<FreeTag, &b2DynamicTree::m_freeList>;
template struct Expose<InsertTag, &b2DynamicTree::m_insertionCount>;

}  // namespace

std::string Broadphase::treeLayoutProblem() {
    if (b2_version.major == 2 && b2_version.minor == 4) return {};
    return "the broadphase tree is saved in Box2D 2.4's layout, but this Talus runs with Box2D " +
           std::to_string(b2_version.major) + "." + std::to_string(b2_version.minor) + "." +
           std::to_string(b2_version.revision) + " (docs/save-format.md, \"Box2D's tree\")";
}

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

// ------------------------------------------------------------------------ save and restore

void Broadphase::save(SaveWriter& w) const {
    if (const std::string why = treeLayoutProblem(); !why.empty()) throw InputError("save: " + why);
    const b2DynamicTree& t = m_impl->tree;
    w.f64(m_margin);
    w.f64(m_impl->scale);
    w.i32(t.*member(RootTag{}));
    w.i32(t.*member(CountTag{}));
    w.i32(t.*member(CapacityTag{}));
    w.i32(t.*member(FreeTag{}));
    w.i32(t.*member(InsertTag{}));
    const b2TreeNode* nodes = t.*member(NodesTag{});
    for (int32 i = 0; i < t.*member(CapacityTag{}); ++i) {
        b2TreeNode n = nodes[i];
        if (n.height == -1) {
            // A free node: only its link counts; Box2D leaves the rest uninitialised. So does
            // b2TreeNode{} for the box: b2Vec2's default constructor is user-provided and sets
            // nothing, so value-initialisation leaves x and y indeterminate. The optimised
            // build happened to write equal bytes for a model and its restored copy; under ASan
            // the temporary held stack garbage (half a pointer, read as a denormal float), so a
            // restored model saved other bytes. Zero it: a save is a function of the state.
            const int32 next = n.next;
            n = b2TreeNode{};
            n.aabb.lowerBound.SetZero();
            n.aabb.upperBound.SetZero();
            n.userData = nullptr;
            n.next = next;
            n.child1 = n.child2 = b2_nullNode;
            n.height = -1;
            n.moved = false;
        } else if (n.child1 != b2_nullNode) {
            // An inner node: its body and moved flag mean nothing, and Box2D may leave them
            // uninitialised; a fixed value keeps a save's bytes a function of the state.
            n.userData = nullptr;
            n.moved = false;
        }
        w.pod(n.aabb.lowerBound.x), w.pod(n.aabb.lowerBound.y);
        w.pod(n.aabb.upperBound.x), w.pod(n.aabb.upperBound.y);
        w.u32(static_cast<uint32_t>(reinterpret_cast<uintptr_t>(n.userData)));
        w.i32(n.parent);
        w.i32(n.child1);
        w.i32(n.child2);
        w.i32(n.height);
        w.boolean(n.moved);
    }
}

namespace {

/// The structure of a restored tree: every node reached once from the root or the free list,
/// children and parents in range and consistent, leaves of height 0, inner nodes one above
/// their highest child (Box2D's balancing relies on the heights to find grandchildren).
void checkTree(const std::vector<b2TreeNode>& nodes, int32 root, int32 count, int32 free_list,
               SaveReader& r) {
    const auto capacity = static_cast<int32>(nodes.size());
    auto in = [&](int32 i) { return i >= 0 && i < capacity; };
    std::vector<uint8_t> seen(nodes.size(), 0);
    std::vector<int32> order, stack;
    if (root != -1) {
        if (nodes[root].parent != -1) r.fail("broadphase: the root has a parent");
        stack.push_back(root);
    }
    while (!stack.empty()) {
        const int32 i = stack.back();
        stack.pop_back();
        if (seen[i]) r.fail("broadphase: node " + std::to_string(i) + " is reached twice");
        seen[i] = 1;
        order.push_back(i);
        const b2TreeNode& n = nodes[i];
        if (n.child1 == b2_nullNode) {
            if (n.child2 != b2_nullNode || n.height != 0)
                r.fail("broadphase: leaf " + std::to_string(i) + " is inconsistent");
            continue;
        }
        if (!in(n.child1) || !in(n.child2) || n.child1 == n.child2)
            r.fail("broadphase: node " + std::to_string(i) + " has an invalid child");
        if (nodes[n.child1].parent != i || nodes[n.child2].parent != i)
            r.fail("broadphase: node " + std::to_string(i) + " is not its children's parent");
        stack.push_back(n.child1);
        stack.push_back(n.child2);
    }
    if (order.size() != static_cast<std::size_t>(count))
        r.fail("broadphase: the tree holds " + std::to_string(order.size()) + " nodes, not " +
               std::to_string(count));
    // Children come after their parent in `order`: check heights from the end.
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
        const b2TreeNode& n = nodes[*it];
        if (n.child1 == b2_nullNode) continue;
        if (n.height != 1 + std::max(nodes[n.child1].height, nodes[n.child2].height))
            r.fail("broadphase: node " + std::to_string(*it) + " has a wrong height");
    }
    int32 free_count = 0;
    for (int32 i = free_list; i != b2_nullNode; i = nodes[i].next) {
        if (!in(i) || seen[i]) r.fail("broadphase: the free list is broken");
        if (nodes[i].height != -1) r.fail("broadphase: a free node has a height");
        seen[i] = 1;
        ++free_count;
    }
    if (count + free_count != capacity) r.fail("broadphase: nodes lost from the tree");
}

}  // namespace

void Broadphase::restore(SaveReader& r) {
    if (const std::string why = treeLayoutProblem(); !why.empty()) r.fail(why);
    const double margin = r.f64();
    const double scale = r.f64();
    if (!(margin > 0.0) || !std::isfinite(margin) || !(scale > 0.0) || !std::isfinite(scale))
        r.fail("broadphase: invalid margin or scale");
    const int32 root = r.i32(), count = r.i32(), capacity = r.i32(), free_list = r.i32(),
                inserted = r.i32();
    constexpr std::size_t kNodeBytes = 4 * 4 + 4 + 4 * 4 + 1;
    if (capacity < 1 || static_cast<std::size_t>(capacity) > r.left() / kNodeBytes)
        r.fail("broadphase: node capacity " + std::to_string(capacity) +
               " does not fit in the section");
    if (count < 0 || count > capacity || root < -1 || root >= capacity || free_list < -1 ||
        free_list >= capacity)
        r.fail("broadphase: invalid tree header");
    std::vector<b2TreeNode> nodes(static_cast<std::size_t>(capacity));
    for (b2TreeNode& n : nodes) {
        n.aabb.lowerBound.x = r.pod<float>(), n.aabb.lowerBound.y = r.pod<float>();
        n.aabb.upperBound.x = r.pod<float>(), n.aabb.upperBound.y = r.pod<float>();
        n.userData = reinterpret_cast<void*>(static_cast<uintptr_t>(r.u32()));
        n.parent = r.i32();
        n.child1 = r.i32();
        n.child2 = r.i32();
        n.height = r.i32();
        n.moved = r.boolean();
    }
    checkTree(nodes, root, count, free_list, r);

    reset(margin);
    m_impl->scale = scale;
    b2DynamicTree& t = m_impl->tree;
    b2Free(t.*member(NodesTag{}));
    auto* mem =
        static_cast<b2TreeNode*>(b2Alloc(capacity * static_cast<int32>(sizeof(b2TreeNode))));
    std::copy(nodes.begin(), nodes.end(), mem);
    t.*member(NodesTag{}) = mem;
    t.*member(RootTag{}) = root;
    t.*member(CountTag{}) = count;
    t.*member(CapacityTag{}) = capacity;
    t.*member(FreeTag{}) = free_list;
    t.*member(InsertTag{}) = inserted;
}

bool Broadphase::isLeaf(int32_t proxy) const {
    const b2DynamicTree& t = m_impl->tree;
    if (proxy < 0 || proxy >= t.*member(CapacityTag{})) return false;
    const b2TreeNode& n = (t.*member(NodesTag{}))[proxy];
    return n.height == 0 && n.child1 == b2_nullNode;
}

std::size_t Broadphase::leafCount() const {
    const b2DynamicTree& t = m_impl->tree;
    std::size_t k = 0;
    for (int32 i = 0; i < t.*member(CapacityTag{}); ++i) k += isLeaf(i);
    return k;
}

}  // namespace talus
