#pragma once
// The error type of the I/O layer: what failed, on which dataset and layer, and GDAL's message.
#include <stdexcept>
#include <string>

namespace trisnap {

/// An input or output that cannot be read or written; main() prints what() and exits 1.
class io_error : public std::runtime_error {
public:
    io_error(const std::string& dataset, const std::string& layer, const std::string& message)
        : std::runtime_error(dataset + (layer.empty() ? "" : " (layer '" + layer + "')") + ": " +
                             message),
          m_dataset(dataset), m_layer(layer)
    {
    }
    const std::string& dataset() const { return m_dataset; }
    const std::string& layer() const { return m_layer; }

private:
    std::string m_dataset;
    std::string m_layer;
};

} // namespace trisnap
