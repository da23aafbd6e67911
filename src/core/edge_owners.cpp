#include "core/edge_owners.hpp"

#include <algorithm>
#include <bit>
#include <utility>

namespace trisnap::detail {

std::size_t EdgeOwners::slot_of(std::uint64_t k) const
{
    // Fibonacci hashing: the top bits of k * 2^64/phi index the table.
    const std::size_t bits = static_cast<std::size_t>(std::countr_zero(m_keys.size()));
    return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> (64 - bits));
}

std::size_t EdgeOwners::find(std::uint64_t k) const
{
    if (m_keys.empty()) {
        return k_none;
    }
    const std::size_t mask = m_keys.size() - 1;
    for (std::size_t s = slot_of(k);; s = (s + 1) & mask) {
        if (m_keys[s] == k) {
            return s;
        }
        if (m_keys[s] == k_empty) {
            return k_none;
        }
    }
}

void EdgeOwners::grow()
{
    std::vector<std::uint64_t> keys(m_keys.empty() ? 64 : 2 * m_keys.size(), k_empty);
    std::vector<std::uint32_t> heads(keys.size(), k_none);
    keys.swap(m_keys);
    heads.swap(m_heads);
    const std::size_t mask = m_keys.size() - 1;
    for (std::size_t s = 0; s < keys.size(); ++s) {
        if (keys[s] == k_empty) {
            continue;
        }
        std::size_t t = slot_of(keys[s]);
        while (m_keys[t] != k_empty) {
            t = (t + 1) & mask;
        }
        m_keys[t] = keys[s];
        m_heads[t] = heads[s];
    }
}

std::size_t EdgeOwners::find_or_insert(std::uint64_t k)
{
    if (2 * (m_count + 1) > m_keys.size()) {
        grow();
    }
    const std::size_t mask = m_keys.size() - 1;
    std::size_t s = slot_of(k);
    while (m_keys[s] != k_empty && m_keys[s] != k) {
        s = (s + 1) & mask;
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
    const std::size_t mask = m_keys.size() - 1;
    std::size_t hole = s;
    for (std::size_t t = (s + 1) & mask; m_keys[t] != k_empty; t = (t + 1) & mask) {
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

void EdgeOwners::rename(const std::vector<std::uint32_t>& rename)
{
    auto renamed = [&](std::uint32_t id) { return id < rename.size() ? rename[id] : id; };
    std::vector<std::pair<std::uint64_t, std::uint32_t>> all;
    all.reserve(m_count);
    for (std::size_t s = 0; s < m_keys.size(); ++s) {
        if (m_keys[s] == k_empty) {
            continue;
        }
        const auto u = static_cast<std::uint32_t>(m_keys[s] >> 32);
        const auto v = static_cast<std::uint32_t>(m_keys[s]);
        const std::uint32_t nu = renamed(u);
        const std::uint32_t nv = renamed(v);
        if (nu > nv) { // the lower end changed: every entry's direction bit flips
            for (std::uint32_t n = m_heads[s]; n != k_none; n = m_nodes[n].next) {
                m_nodes[n].packed ^= 1u;
            }
        }
        all.emplace_back(key(nu, nv), m_heads[s]);
    }
    std::fill(m_keys.begin(), m_keys.end(), k_empty);
    const std::size_t mask = m_keys.size() - 1;
    for (const auto& [k, head] : all) {
        std::size_t s = slot_of(k);
        while (m_keys[s] != k_empty) {
            s = (s + 1) & mask;
        }
        m_keys[s] = k;
        m_heads[s] = head;
    }
}

} // namespace trisnap::detail
