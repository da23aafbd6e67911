#pragma once
// Byte-level encoding of the work directory's records: fixed-width integers and doubles in the
// machine's byte order, bit for bit (a double goes in and comes out with the same bits, NaN
// payloads and negative zeros included). A work directory is read by the machines of one
// cluster, all little-endian; the run's manifest records the byte order and refuses another.
#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

namespace trisnap::tiling {

static_assert(std::endian::native == std::endian::little, "work directories are little-endian");

/// A record that does not decode (truncated or from another format): the work directory is
/// damaged. what() names the record kind.
class record_error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Appends values to a byte string.
class ByteWriter {
public:
    explicit ByteWriter(std::string& out) : m_out(out) {}
    template <typename T>
    void put(T value)
    {
        static_assert(std::is_trivially_copyable_v<T>);
        char bytes[sizeof(T)];
        std::memcpy(bytes, &value, sizeof(T));
        m_out.append(bytes, sizeof(T));
    }
    void put_string(std::string_view s)
    {
        put<std::uint32_t>(static_cast<std::uint32_t>(s.size()));
        m_out.append(s);
    }
    std::size_t size() const { return m_out.size(); }

private:
    std::string& m_out;
};

/// Reads values back in the order they were put; throws record_error past the end.
class ByteReader {
public:
    ByteReader(std::string_view in, const char* what) : m_in(in), m_what(what) {}
    template <typename T>
    T get()
    {
        static_assert(std::is_trivially_copyable_v<T>);
        need(sizeof(T));
        T value;
        std::memcpy(&value, m_in.data() + m_pos, sizeof(T));
        m_pos += sizeof(T);
        return value;
    }
    std::string get_string()
    {
        const auto n = get<std::uint32_t>();
        need(n);
        std::string s(m_in.substr(m_pos, n));
        m_pos += n;
        return s;
    }
    /// A count of items of at least `item_bytes` each that must still fit in the input.
    std::uint32_t get_count(std::size_t item_bytes)
    {
        const auto n = get<std::uint32_t>();
        need(static_cast<std::size_t>(n) * item_bytes);
        return n;
    }
    /// Skips n bytes that must be there.
    void skip(std::size_t n)
    {
        need(n);
        m_pos += n;
    }
    bool done() const { return m_pos == m_in.size(); }
    std::size_t remaining() const { return m_in.size() - m_pos; }
    std::size_t position() const { return m_pos; }

private:
    void need(std::size_t n) const
    {
        if (n > m_in.size() - m_pos) {
            throw record_error(std::string("damaged work file: truncated ") + m_what + " record");
        }
    }

    std::string_view m_in;
    const char* m_what;
    std::size_t m_pos = 0;
};

} // namespace trisnap::tiling
