#include "core/edge_owners.hpp"

#include <algorithm>
#include <utility>

namespace trisnap::detail {

std::size_t EdgeOwners::slot_of(std::uint64_t k) const
{
    // Fibonacci hashing, then the mixed key's fraction of the table (a multiply and a shift:
    // any table size, no modulo).
    const std::uint64_t mixed = k * 0x9E3779B97F4A7C15ull;
    return static_cast<std::size_t>((static_cast<unsigned __int128>(mixed) * m_keys.size()) >> 64);
}

std::size_t EdgeOwners::find(std::uint64_t k) const
{
    if (m_keys.empty()) {
        return k_none;
    }
    for (std::size_t s = slot_of(k);; s = next(s)) {
        if (m_keys[s] == k) {
            return s;
        }
        if (m_keys[s] == k_empty) {
            return k_none;
        }
    }
}

void EdgeOwners::reserve(std::size_t edges, std::size_t entries)
{
    if (slots_for(edges) > m_keys.size()) {
        resize(slots_for(edges));
    }
    m_nodes.reserve(entries);
}

// The table rebuilt with `slots` slots, its keys put in again in slot order.
void EdgeOwners::resize(std::size_t slots)
{
    std::vector<std::uint64_t> keys(slots, k_empty);
    std::vector<std::uint32_t> heads(slots, k_none);
    keys.swap(m_keys);
    heads.swap(m_heads);
    for (std::size_t s = 0; s < keys.size(); ++s) {
        if (keys[s] == k_empty) {
            continue;
        }
        std::size_t t = slot_of(keys[s]);
        while (m_keys[t] != k_empty) {
            t = next(t);
        }
        m_keys[t] = keys[s];
        m_heads[t] = heads[s];
    }
}

std::size_t EdgeOwners::find_or_insert(std::uint64_t k)
{
    if (10 * (m_count + 1) > 7 * m_keys.size()) {
        resize(m_keys.empty() ? slots_for(0) : m_keys.size() + m_keys.size() / 2);
    }
    std::size_t s = slot_of(k);
    while (m_keys[s] != k_empty && m_keys[s] != k) {
        s = next(s);
    }
    if (m_keys[s] == k_empty) {
        m_keys[s] = k;
        m_heads[s] = k_none;
        ++m_count;
    }
    return s;
}

// Backward-shift deletion: later keys of the probe run move up, so no tombstones accumulate.
void EdgeOwners::erase_slot(std::size_t s)
{
    std::size_t hole = s;
    for (std::size_t t = next(s); m_keys[t] != k_empty; t = next(t)) {
        const std::size_t home = slot_of(m_keys[t]);
        const bool movable = hole <= t ? (home <= hole || home > t) : (home <= hole && home > t);
        if (movable) {
            m_keys[hole] = m_keys[t];
            m_heads[hole] = m_heads[t];
            hole = t;
        }
    }
    m_keys[hole] = k_empty;
    m_heads[hole] = k_none;
    --m_count;
}

std::uint32_t EdgeOwners::new_node(std::uint32_t packed, std::uint32_t next)
{
    if (m_free != k_none) {
        const std::uint32_t n = m_free;
        m_free = m_nodes[n].next;
        m_nodes[n] = Node{packed, next};
        return n;
    }
    m_nodes.push_back(Node{packed, next});
    return static_cast<std::uint32_t>(m_nodes.size() - 1);
}

bool EdgeOwners::add(std::uint32_t from, std::uint32_t to, OwnerRef ref)
{
    const bool low_to_high = (from < to) == ref.forward;
    const std::uint32_t packed = (ref.owner << 1) | (low_to_high ? 1u : 0u);
    const std::size_t s = find_or_insert(key(from, to));
    // Appended at the tail so entries keep the order they were added in.
    const std::uint32_t node = new_node(packed, k_none);
    if (m_heads[s] == k_none) {
        m_heads[s] = node;
        return true;
    }
    std::uint32_t n = m_heads[s];
    while (m_nodes[n].next != k_none) {
        n = m_nodes[n].next;
    }
    m_nodes[n].next = node;
    return false;
}

void EdgeOwners::append(std::uint32_t head, bool flip, std::vector<OwnerRef>& out) const
{
    for (std::uint32_t n = head; n != k_none; n = m_nodes[n].next) {
        OwnerRef r = unpack(m_nodes[n].packed);
        r.forward = r.forward != flip;
        out.push_back(r);
    }
}

void EdgeOwners::get(std::uint32_t from, std::uint32_t to, std::vector<OwnerRef>& out) const
{
    const std::size_t s = find(key(from, to));
    if (s != k_none) {
        append(m_heads[s], from > to, out);
    }
}

void EdgeOwners::take(std::uint32_t from, std::uint32_t to, std::vector<OwnerRef>& out)
{
    const std::size_t s = find(key(from, to));
    if (s == k_none) {
        return;
    }
    append(m_heads[s], from > to, out);
    std::uint32_t n = m_heads[s];
    while (n != k_none) {
        const std::uint32_t next = m_nodes[n].next;
        m_nodes[n].next = m_free;
        m_free = n;
        n = next;
    }
    erase_slot(s);
}

// Only the edges with a renamed end move: they are taken out first (backward shift, as take()),
// then put in under their new keys, so a new key never meets an old one still in the table (a
// renaming is one-to-one). The full rebuild this replaces copied the whole table (16 bytes an
// edge: 29 MB on Andorra x43 untiled) for the few edges at crossing vertices, 3 % of Natural Earth
// countries' run.
void EdgeOwners::rename(const std::vector<std::uint32_t>& rename)
{
    auto renamed = [&](std::uint32_t id) { return id < rename.size() ? rename[id] : id; };
    std::vector<std::pair<std::uint64_t, std::uint64_t>> moved; // old key, new key
    for (const std::uint64_t k : m_keys) {
        if (k == k_empty) {
            continue;
        }
        const auto u = static_cast<std::uint32_t>(k >> 32);
        const auto v = static_cast<std::uint32_t>(k);
        if (renamed(u) != u || renamed(v) != v) {
            moved.emplace_back(k, key(renamed(u), renamed(v)));
        }
    }
    std::vector<std::uint32_t> heads(moved.size());
    for (std::size_t i = 0; i < moved.size(); ++i) {
        const std::size_t s = find(moved[i].first);
        heads[i] = m_heads[s];
        const auto u = static_cast<std::uint32_t>(moved[i].first >> 32);
        const auto v = static_cast<std::uint32_t>(moved[i].first);
        if (renamed(u) > renamed(v)) { // the lower end changed: every entry's direction bit flips
            for (std::uint32_t n = heads[i]; n != k_none; n = m_nodes[n].next) {
                m_nodes[n].packed ^= 1u;
            }
        }
        erase_slot(s);
    }
    for (std::size_t i = 0; i < moved.size(); ++i) {
        m_heads[find_or_insert(moved[i].second)] = heads[i];
    }
}

} // namespace trisnap::detail
