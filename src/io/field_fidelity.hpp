#pragma once
// What the output driver does to attribute values and field names that it cannot hold, found by
// comparing what we set with what the output field can store. ogr2ogr warns once per layer (or
// not at all: a Shapefile writes 1e-300 as 0 silently); here every changed value is a problem
// with its FID and field (903), every renamed field a problem of the layer (904, FID -1), and
// each kind of change gets one summary line for stderr.
//
// What is compared, for every driver: a value whose output field has another type than its
// input field (Real into Integer, DateTime into Date, ...) must read back the same. For the
// Shapefile driver (dBASE) also what the .dbf stores: strings longer than 254 bytes are cut, a
// Real is printed with the field's width and decimals (too wide: cut; too small: rounded, kept
// when it reads back within 1e-12 relative), a date's year must be 0..9999. Not modelled: other
// drivers' own limits (their per-feature warnings are left to GDAL's log).
#include "core/problems.hpp"

#include <ogrsf_frmts.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace trisnap {

class FieldFidelity {
public:
    /// `field_map[i]` is the output field of input field i; `driver` the output driver's name.
    /// Keeps no reference to either definition.
    FieldFidelity(const OGRFeatureDefn& input, const OGRFeatureDefn& output, const std::vector<int>& field_map,
                  const std::string& driver);

    /// Problems 904 for fields whose output name differs from the input name (FID -1).
    const std::vector<Problem>& renamed_fields() const { return m_renamed; }

    /// Appends a problem 903 for every value of `source` that `written` (the output feature as
    /// handed to the driver) does not keep.
    void check(const OGRFeature& source, const OGRFeature& written, std::int64_t fid, std::vector<Problem>& out);

    /// One line per field and kind of change: "field 'name': 3 values cut to 254 bytes (first FID 7)".
    std::vector<std::string> summary() const;

private:
    struct Tally {
        std::size_t count = 0;
        std::int64_t first_fid = 0;
    };
    std::vector<std::string> m_names; ///< input field names
    std::vector<int> m_field_map;
    std::vector<Problem> m_renamed;
    bool m_dbf = false;
    std::map<std::pair<std::string, std::string>, Tally> m_tallies; ///< (field, kind) -> count
};

} // namespace trisnap
