// The assessor's hand-written exact predicates and its STR tree against references: CGAL's exact
// predicates (Exact_predicates_exact_constructions_kernel) and brute force, on random and
// adversarial input (near-collinear points a few ulps off a line, huge and tiny coordinates,
// mixed magnitudes, repeated points, degenerate boxes).
#include "assess/geometry.hpp"
#include "assess/str_tree.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace trisnap::assess {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;

K::Point_2 cgal(Pt p) { return K::Point_2(p.x, p.y); }

int reference_orient(Pt a, Pt b, Pt c)
{
    return static_cast<int>(CGAL::orientation(cgal(a), cgal(b), cgal(c)));
}

std::string text(Pt a, Pt b, Pt c)
{
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, "(%a %a) (%a %a) (%a %a)", a.x, a.y, b.x, b.y, c.x, c.y);
    return buffer;
}

/// Counts disagreements with CGAL (and prints the first few).
std::size_t orient_mismatches(const std::vector<std::array<Pt, 3>>& triples)
{
    std::size_t bad = 0;
    for (const auto& [a, b, c] : triples) {
        const int want = reference_orient(a, b, c);
        if (orient(a, b, c) != want) {
            if (++bad <= 5) {
                ADD_FAILURE() << "orient " << text(a, b, c) << " = " << orient(a, b, c) << ", CGAL says " << want;
            }
        }
    }
    return bad;
}

std::vector<std::array<Pt, 3>> random_triples(std::mt19937_64& rng, double scale, Pt offset, std::size_t n)
{
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<std::array<Pt, 3>> out;
    for (std::size_t i = 0; i < n; ++i) {
        std::array<Pt, 3> t;
        for (Pt& p : t) {
            p = {offset.x + scale * u(rng), offset.y + scale * u(rng)};
        }
        out.push_back(t);
    }
    return out;
}

/// c on the line a-b as far as doubles allow, then moved k ulps in x and/or y: the sign is
/// decided by bits far below the filter's reach.
std::vector<std::array<Pt, 3>> near_collinear(std::mt19937_64& rng, double scale, Pt offset, std::size_t n)
{
    std::uniform_real_distribution<double> u(-1.0, 1.0), along(-0.5, 1.5);
    std::uniform_int_distribution<int> ulps(-3, 3);
    std::vector<std::array<Pt, 3>> out;
    for (std::size_t i = 0; i < n; ++i) {
        const Pt a{offset.x + scale * u(rng), offset.y + scale * u(rng)};
        const Pt b{offset.x + scale * u(rng), offset.y + scale * u(rng)};
        const double s = along(rng);
        Pt c{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)};
        for (int k = ulps(rng); k != 0; k += k > 0 ? -1 : 1) {
            c.x = std::nextafter(c.x, k > 0 ? HUGE_VAL : -HUGE_VAL);
        }
        for (int k = ulps(rng); k != 0; k += k > 0 ? -1 : 1) {
            c.y = std::nextafter(c.y, k > 0 ? HUGE_VAL : -HUGE_VAL);
        }
        out.push_back({a, b, c});
    }
    return out;
}

const double k_scales[] = {1.0, 1e-300, 1e-200, 1e-150, 1e-20, 1e20, 1e150, 1e200, 1e300};

TEST(AssessExactOrient, RandomPointsAgreeWithCgalAtEveryScale)
{
    std::mt19937_64 rng(11);
    for (double scale : k_scales) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        EXPECT_EQ(orient_mismatches(random_triples(rng, scale, {0, 0}, 2000)), 0u);
    }
}

TEST(AssessExactOrient, NearCollinearPointsAgreeWithCgal)
{
    std::mt19937_64 rng(12);
    const Pt offsets[] = {{0, 0}, {4.35, 52.0}, {84700, 447450}, {-1e6, 3e6}};
    for (double scale : k_scales) {
        for (Pt offset : offsets) {
            SCOPED_TRACE("scale " + std::to_string(scale) + " offset " + std::to_string(offset.x));
            EXPECT_EQ(orient_mismatches(near_collinear(rng, scale, {offset.x * scale, offset.y * scale}, 1000)), 0u);
        }
    }
}

TEST(AssessExactOrient, ShewchukGridNearTheDiagonal)
{
    // Points 0.5 + i*2^-53 on both axes around the line y = x: the classic case where a plain
    // double determinant gets the sign wrong.
    std::vector<std::array<Pt, 3>> triples;
    const double ulp = std::ldexp(1.0, -53);
    for (int i = 0; i < 64; ++i) {
        for (int j = 0; j < 64; ++j) {
            triples.push_back({Pt{0.5 + i * ulp, 0.5 + j * ulp}, Pt{12, 12}, Pt{24, 24}});
        }
    }
    EXPECT_EQ(orient_mismatches(triples), 0u);
}

TEST(AssessExactOrient, MixedMagnitudesAndRepeatedPoints)
{
    std::mt19937_64 rng(13);
    std::uniform_int_distribution<int> exponent(-1070, 1020);
    std::uniform_int_distribution<int> sign(0, 1);
    auto value = [&] { return (sign(rng) ? -1.0 : 1.0) * std::ldexp(1.0 + exponent(rng) % 7 / 8.0, exponent(rng)); };
    std::vector<std::array<Pt, 3>> triples;
    for (int i = 0; i < 5000; ++i) {
        const Pt a{value(), value()}, b{value(), value()}, c{value(), value()};
        triples.push_back({a, b, c});
        triples.push_back({a, a, c});
        triples.push_back({a, b, Pt{a.x, b.y}});
    }
    triples.push_back({Pt{0, 0}, Pt{1e300, 1e300}, Pt{-1e300, -1e300}});
    triples.push_back({Pt{1e-300, 0}, Pt{0, 1e-300}, Pt{0, 0}});
    triples.push_back({Pt{5e-324, 0}, Pt{0, 5e-324}, Pt{5e-324, 5e-324}});
    triples.push_back({Pt{1.7e308, 1.7e308}, Pt{-1.7e308, 1.7e308}, Pt{0, -1.7e308}});
    EXPECT_EQ(orient_mismatches(triples), 0u);
}

TEST(AssessExactOrient, SegmentContactAgreesWithCgalOnMeetingOrNot)
{
    std::mt19937_64 rng(14);
    std::size_t bad = 0;
    for (double scale : k_scales) {
        const auto triples = near_collinear(rng, scale, {0, 0}, 2000);
        for (std::size_t i = 0; i + 1 < triples.size(); i += 2) {
            const Pt p1 = triples[i][0], q1 = triples[i][1];
            const Pt p2 = triples[i][2], q2 = i % 4 == 0 ? triples[i + 1][2] : triples[i + 1][0];
            const bool meet = segment_contact(p1, q1, p2, q2) != SegmentContact::none;
            const bool want = CGAL::do_intersect(K::Segment_2(cgal(p1), cgal(q1)), K::Segment_2(cgal(p2), cgal(q2)));
            if (meet != want && ++bad <= 5) {
                ADD_FAILURE() << "segment_contact " << text(p1, q1, p2) << " - " << q2.x << " " << q2.y
                              << ": meet " << meet << ", CGAL " << want;
            }
        }
    }
    EXPECT_EQ(bad, 0u);
}

// ---- STR tree against brute force -----------------------------------------------------------

std::vector<Box> random_boxes(std::mt19937_64& rng, std::size_t n, double scale, bool degenerate)
{
    std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.0, 0.05);
    std::vector<Box> boxes;
    for (std::size_t i = 0; i < n; ++i) {
        Box b;
        const Pt p{scale * u(rng), scale * u(rng)};
        b.add(p);
        if (!degenerate || i % 3 != 0) {
            // long thin boxes every 7th item, points every 3rd when degenerate
            const double w = i % 7 == 0 ? 1.5 : size(rng), h = i % 7 == 0 ? 1e-9 : size(rng);
            b.add(Pt{p.x + scale * w, p.y + scale * h});
        }
        boxes.push_back(b);
    }
    return boxes;
}

std::vector<std::uint32_t> brute_query(const std::vector<Box>& boxes, const Box& q)
{
    std::vector<std::uint32_t> ids;
    for (std::uint32_t i = 0; i < boxes.size(); ++i) {
        if (boxes[i].intersects(q)) {
            ids.push_back(i);
        }
    }
    return ids;
}

void expect_tree_matches_brute_force(const std::vector<Box>& boxes, double scale, std::mt19937_64& rng)
{
    const StrTree tree(boxes);
    std::uniform_real_distribution<double> u(-1.2, 1.2), size(0.0, 0.3);
    for (int k = 0; k < 200; ++k) {
        Box q;
        const Pt p{scale * u(rng), scale * u(rng)};
        q.add(p);
        q.add(Pt{p.x + scale * size(rng), p.y + scale * size(rng)});
        std::vector<std::uint32_t> got;
        tree.query(q, [&](std::uint32_t id) { got.push_back(id); });
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, brute_query(boxes, q)) << "query " << k;
        auto dist = [&](std::uint32_t id) { return boxes[id].distance(p); };
        double best = k_inf;
        for (std::uint32_t i = 0; i < boxes.size(); ++i) {
            best = std::min(best, dist(i));
        }
        const auto [id, d] = tree.nearest(p, dist);
        ASSERT_EQ(d, best) << "nearest " << k;
        if (!boxes.empty()) {
            ASSERT_EQ(dist(id), best);
        }
    }
}

TEST(AssessStrTree, QueriesAndNearestMatchBruteForce)
{
    std::mt19937_64 rng(21);
    for (std::size_t n : {0u, 1u, 15u, 16u, 17u, 255u, 256u, 257u, 4099u}) {
        for (double scale : {1.0, 1e-150, 1e150}) {
            for (bool degenerate : {false, true}) {
                SCOPED_TRACE("n " + std::to_string(n) + " scale " + std::to_string(scale));
                expect_tree_matches_brute_force(random_boxes(rng, n, scale, degenerate), scale, rng);
            }
        }
    }
}

TEST(AssessStrTree, ManyIdenticalAndCollinearBoxes)
{
    std::mt19937_64 rng(22);
    std::vector<Box> same(1000);
    for (Box& b : same) {
        b.add(Pt{0.25, 0.25});
        b.add(Pt{0.5, 0.5});
    }
    expect_tree_matches_brute_force(same, 1.0, rng);
    std::vector<Box> line;
    for (int i = 0; i < 3000; ++i) {
        Box b;
        b.add(Pt{i * 1e-3 - 1.0, 0.0});
        line.push_back(b);
    }
    expect_tree_matches_brute_force(line, 1.0, rng);
}

} // namespace
} // namespace trisnap::assess
