#pragma once
// Who owns each constrained edge of the triangulation: the flat table the engine edits itself
// (CGAL's plain constrained triangulation only flags an edge as constrained).
//
// An edge is the pair of its vertex ids; its entries are the input edges running along it, each
// with the direction it runs in. Two owners from one feature stay two entries (overlapping
// rings: labelling counts their parity), and so does one owner twice (a vertex merge folded
// two of its pieces onto one edge). Open addressing with linear probing, entries in a pooled
// linked list per edge: no allocation per edge. The table is sized for the edges the caller
// expects (reserve) and kept at most 70 % full, growing by half: 12 bytes a slot, 17-26 a
// distinct edge while it grows, and 8 an entry. The build reserves for its input edges, an upper
// bound: ~17 bytes of slots per input edge whatever they share, so per distinct edge 17 times
// the rings along it (34 in a coverage, more where rings are stacked on each other). A
// power-of-two table at most half full, as before, took 24-48 per distinct edge, and held
// Andorra x43's 1.63 M edges in 4.19 M slots. Nothing the engine computes depends on the
// table's order: a tile's table and the whole layer's differ, and their outputs are the same.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace trisnap::detail {

/// An input edge (index into the Mesh's owner table) and whether it runs along the edge in the
/// direction the holder of this value looks at it (from -> to).
struct OwnerRef {
    std::uint32_t owner = 0;
    bool forward = true;
};

class EdgeOwners {
public:
    /// Adds an owner to the edge from-to (creating the edge), running from -> to when `forward`.
    /// Returns whether the edge was created.
    bool add(std::uint32_t from, std::uint32_t to, OwnerRef ref);
    /// Appends the owners of from-to to `out`, oriented from -> to, and removes the edge.
    void take(std::uint32_t from, std::uint32_t to, std::vector<OwnerRef>& out);
    /// Appends the owners of from-to to `out`, oriented from -> to.
    void get(std::uint32_t from, std::uint32_t to, std::vector<OwnerRef>& out) const;
    bool contains(std::uint32_t a, std::uint32_t b) const { return find(key(a, b)) != k_none; }
    std::size_t edges() const { return m_count; }
    /// Room for `edges` edges and `entries` entries in all without growing.
    void reserve(std::size_t edges, std::size_t entries);
    /// The table's slots (for the tests).
    std::size_t slots() const { return m_keys.size(); }

    /// Calls f(u, v, OwnerRef) for every entry, u < v, oriented u -> v; order is the table's.
    template <class F>
    void for_each(F&& f) const
    {
        for (std::size_t s = 0; s < m_keys.size(); ++s) {
            if (m_keys[s] == k_empty) {
                continue;
            }
            const auto u = static_cast<std::uint32_t>(m_keys[s] >> 32);
            const auto v = static_cast<std::uint32_t>(m_keys[s]);
            for (std::uint32_t n = m_heads[s]; n != k_none; n = m_nodes[n].next) {
                f(u, v, unpack(m_nodes[n].packed));
            }
        }
    }

    /// Calls f(u, v, std::span<const OwnerRef>) once for every edge with all its entries, u < v,
    /// oriented u -> v (gathered in `buffer`); order is the table's.
    template <class F>
    void for_each_grouped(F&& f, std::vector<OwnerRef>& buffer) const
    {
        for (std::size_t s = 0; s < m_keys.size(); ++s) {
            if (m_keys[s] == k_empty) {
                continue;
            }
            buffer.clear();
            for (std::uint32_t n = m_heads[s]; n != k_none; n = m_nodes[n].next) {
                buffer.push_back(unpack(m_nodes[n].packed));
            }
            f(static_cast<std::uint32_t>(m_keys[s] >> 32), static_cast<std::uint32_t>(m_keys[s]),
              std::span<const OwnerRef>(buffer));
        }
    }
    /// Calls f(u, v) once for every edge, u < v; order is the table's.
    template <class F>
    void for_each_edge(F&& f) const
    {
        for (const std::uint64_t k : m_keys) {
            if (k != k_empty) {
                f(static_cast<std::uint32_t>(k >> 32), static_cast<std::uint32_t>(k));
            }
        }
    }

    /// Renames vertex ids: id -> rename[id] (ids past the end keep theirs).
    void rename(const std::vector<std::uint32_t>& rename);

private:
    static constexpr std::uint64_t k_empty = 0; // no edge joins vertex 0 to itself
    static constexpr std::uint32_t k_none = std::numeric_limits<std::uint32_t>::max();
    struct Node {
        std::uint32_t packed; ///< owner << 1 | runs from the lower id to the higher
        std::uint32_t next;
    };

    static std::uint64_t key(std::uint32_t a, std::uint32_t b)
    {
        return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
    }
    static OwnerRef unpack(std::uint32_t packed) { return OwnerRef{packed >> 1, (packed & 1u) != 0}; }
    /// Slots for `edges` at most 70 % full.
    static std::size_t slots_for(std::size_t edges) { return std::max<std::size_t>(64, edges + edges * 3 / 7 + 1); }
    std::size_t next(std::size_t s) const { return s + 1 == m_keys.size() ? 0 : s + 1; }
    std::size_t slot_of(std::uint64_t k) const;
    std::size_t find(std::uint64_t k) const;
    std::size_t find_or_insert(std::uint64_t k);
    void erase_slot(std::size_t s);
    void resize(std::size_t slots);
    std::uint32_t new_node(std::uint32_t packed, std::uint32_t next);
    void append(std::uint32_t head, bool flip, std::vector<OwnerRef>& out) const;

    std::vector<std::uint64_t> m_keys;
    std::vector<std::uint32_t> m_heads;
    std::vector<Node> m_nodes;
    std::uint32_t m_free = k_none;
    std::size_t m_count = 0;
};

} // namespace trisnap::detail
