#pragma once
// Decodes fuzz bytes into a small snapping problem: options (tolerance, edge separation, sliver
// factor, grid, operation cap) and up to 6 features of up to 3 parts or rings of up to 12
// vertices. Tolerances and coordinates are either raw doubles (any bit pattern: NaN, infinities,
// 1e308, subnormals) or decoded on a grid around the tolerance, so that most inputs make the
// engine snap something. The same bytes always decode to the same problem.
#include "core/geometry.hpp"
#include "core/snap.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace trisnap::fuzz {

/// Reads bytes front to back; past the end every read gives zeros.
class ByteReader {
public:
    ByteReader(const std::uint8_t* data, std::size_t size) : m_data(data), m_size(size) {}
    std::uint8_t byte();
    std::uint16_t u16();
    double raw_double();
    bool done() const { return m_pos >= m_size; }

private:
    const std::uint8_t* m_data;
    std::size_t m_size;
    std::size_t m_pos = 0;
};

struct SnapProblem {
    SnapOptions options;
    std::vector<Feature> features;
};

SnapProblem decode_snap_problem(const std::uint8_t* data, std::size_t size);

/// `id;WKT` lines and the options, exactly (hexadecimal floats), to reproduce a failure by hand.
std::string describe(const SnapProblem& problem);

} // namespace trisnap::fuzz
