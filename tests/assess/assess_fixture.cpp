#include "assess_fixture.hpp"

#include <gtest/gtest.h>
#include <fmt/format.h>

#include <stdexcept>

namespace trisnap::test {

GDALDatasetUniquePtr make_layer(const std::vector<Item>& items, OGRwkbGeometryType type, const std::string& driver_name,
                                const std::string& path)
{
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name.c_str());
    if (!driver) throw std::runtime_error("no GDAL driver " + driver_name);
    GDALDatasetUniquePtr ds(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    if (!ds) throw std::runtime_error("cannot create " + path);
    OGRLayer* layer = ds->CreateLayer("l", nullptr, type, nullptr);
    OGRFieldDefn field("name", OFTString);
    layer->CreateField(&field);
    for (const Item& item : items) {
        OGRFeatureUniquePtr f(OGRFeature::CreateFeature(layer->GetLayerDefn()));
        f->SetFID(item.fid);
        f->SetField("name", item.name.c_str());
        if (!item.wkt.empty()) {
            OGRGeometry* g = nullptr;
            if (OGRGeometryFactory::createFromWkt(item.wkt.c_str(), nullptr, &g) != OGRERR_NONE)
                throw std::runtime_error("bad WKT " + item.wkt);
            f->SetGeometryDirectly(g);
        }
        if (layer->CreateFeature(f.get()) != OGRERR_NONE) throw std::runtime_error("cannot write a feature");
    }
    return ds;
}

AssessReport assess_items(const std::vector<Item>& in, const std::vector<Item>& out, double tolerance,
                          const std::string& key)
{
    return assess_items(in, out, AssessOptions{tolerance, key, 20});
}

AssessReport assess_items(const std::vector<Item>& in, const std::vector<Item>& out, const AssessOptions& options)
{
    GDALDatasetUniquePtr a = make_layer(in);
    GDALDatasetUniquePtr b = make_layer(out);
    return assess_layers({*a, *a->GetLayer(0)}, {*b, *b->GetLayer(0)}, options);
}

std::string square(double x0, double y0, double s)
{
    return fmt::format("POLYGON(({0} {1},{2} {1},{2} {3},{0} {3},{0} {1}))", x0, y0, x0 + s, y0 + s);
}

} // namespace trisnap::test
