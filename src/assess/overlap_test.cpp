#include "assess/overlap_test.hpp"
#include "assess/str_tree.hpp"

#include <algorithm>

namespace trisnap::assess {
namespace {

/// A segment with a < b and the side its feature's interior lies on, looking from a to b.
struct SideSeg {
    Pt a, b;
    bool left;
};

bool by_ends(const SideSeg& x, const SideSeg& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); }

std::vector<SideSeg> window_segments(const LayerData& d, const std::vector<std::int8_t>& interior_left,
                                     const Feature& f, const Box& window)
{
    std::vector<SideSeg> out;
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i) {
        if (d.parts[i].type == PartType::line) {
            continue;
        }
        for (std::uint32_t k = d.parts[i].begin; k + 1 < d.parts[i].end; ++k) {
            Pt p = d.pts[k], q = d.pts[k + 1];
            if (p == q || !segment_box(p, q).intersects(window)) {
                continue;
            }
            bool left = interior_left[i] != 0;
            if (q < p) {
                std::swap(p, q);
                left = !left;
            }
            out.push_back({p, q, left});
        }
    }
    std::sort(out.begin(), out.end(), by_ends);
    return out;
}

enum class Contact { none, clean, crossing };

/// How the two boundaries meet: not at all, only at common vertices and identical segments, or otherwise.
Contact contact(const std::vector<SideSeg>& sa, const std::vector<SideSeg>& sb)
{
    Contact result = Contact::none;
    const auto pair = [&](const SideSeg& x, const SideSeg& y) {
        const SegmentContact c = segment_contact(x.a, x.b, y.a, y.b);
        if (c == SegmentContact::crossing) {
            result = Contact::crossing;
        } else if (c != SegmentContact::none) {
            result = Contact::clean;
        }
        return result == Contact::crossing;
    };
    if (sa.size() * sb.size() <= 1024) {
        for (const SideSeg& x : sa) {
            for (const SideSeg& y : sb) {
                if (pair(x, y)) {
                    return result;
                }
            }
        }
        return result;
    }
    std::vector<Box> boxes;
    for (const SideSeg& y : sb) {
        boxes.push_back(segment_box(y.a, y.b));
    }
    const StrTree tree(std::move(boxes));
    for (const SideSeg& x : sa) {
        tree.query(segment_box(x.a, x.b), [&](std::uint32_t j) { if (result != Contact::crossing) pair(x, sb[j]); });
        if (result == Contact::crossing) {
            return result;
        }
    }
    return result;
}

/// True when a segment of `from` lies inside `other`, or shares a segment with it on the same side.
bool inside_or_same_side(const LayerData& d, const std::vector<SideSeg>& from, const std::vector<SideSeg>& to,
                         const Feature& other)
{
    for (const SideSeg& x : from) {
        const auto it = std::lower_bound(to.begin(), to.end(), x, by_ends);
        if (it != to.end() && it->a == x.a && it->b == x.b) {
            if (it->left == x.left) {
                return true;
            }
            continue;
        }
        if (d.strictly_inside(other, {0.5 * (x.a.x + x.b.x), 0.5 * (x.a.y + x.b.y)})) {
            return true;
        }
    }
    return false;
}

} // namespace

std::vector<std::int8_t> interior_left_of_parts(const LayerData& d)
{
    std::vector<std::int8_t> left(d.parts.size(), 0);
    for (std::size_t i = 0; i < d.parts.size(); ++i) {
        const Part& part = d.parts[i];
        if (part.type == PartType::line) {
            continue;
        }
        double twice = 0;
        const Pt o = d.pts[part.begin];
        for (std::uint32_t k = part.begin; k + 1 < part.end; ++k) {
            twice += (d.pts[k].x - o.x) * (d.pts[k + 1].y - o.y) - (d.pts[k + 1].x - o.x) * (d.pts[k].y - o.y);
        }
        // A counter-clockwise shell has its interior on the left; the polygon's interior is outside a hole.
        left[i] = (part.type == PartType::shell) == (twice > 0);
    }
    return left;
}

OverlapVerdict interiors_meet(const LayerData& d, const std::vector<std::int8_t>& interior_left, const Feature& fa,
                              const Feature& fb)
{
    const Box window = fa.box.intersection(fb.box);
    const std::vector<SideSeg> sa = window_segments(d, interior_left, fa, window);
    const std::vector<SideSeg> sb = window_segments(d, interior_left, fb, window);
    switch (contact(sa, sb)) {
    case Contact::crossing: return OverlapVerdict::unknown;
    case Contact::none: // disjoint boundaries: the interiors meet only if one holds the other's vertex
        return d.strictly_inside(fb, d.anchor(fa)) || d.strictly_inside(fa, d.anchor(fb)) ? OverlapVerdict::overlap
                                                                                            : OverlapVerdict::disjoint;
    case Contact::clean: break;
    }
    // Each midpoint test walks the other feature: keep big pairs for GEOS.
    if (sa.size() * d.segment_count(fb) + sb.size() * d.segment_count(fa) > 200000) {
        return OverlapVerdict::unknown;
    }
    if (inside_or_same_side(d, sa, sb, fb) || inside_or_same_side(d, sb, sa, fa)) {
        return OverlapVerdict::overlap;
    }
    return OverlapVerdict::disjoint;
}

} // namespace trisnap::assess
