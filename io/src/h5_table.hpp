#pragma once
// Private to dorado_io: a one-dimensional HDF5 table of compound rows (RadarScenes' radar_data and
// odometry), read column by column over a range of rows, with errors naming the file, the table
// and the field.

#include <hdf5.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace dorado::io {

/// Owns one HDF5 identifier and closes it with the matching H5?close.
class H5Id {
  public:
    using Close = herr_t (*)(hid_t);
    H5Id() = default;
    H5Id(hid_t id, Close close) : id_(id), close_(close) {}
    H5Id(const H5Id &) = delete;
    H5Id &operator=(const H5Id &) = delete;
    H5Id(H5Id &&other) noexcept { *this = std::move(other); }
    H5Id &operator=(H5Id &&other) noexcept;
    ~H5Id();
    [[nodiscard]] hid_t get() const { return id_; }
    [[nodiscard]] bool valid() const { return id_ >= 0; }

  private:
    hid_t id_ = -1;
    Close close_ = nullptr;
};

/// An HDF5 file opened read-only. Throws DatasetError naming the file when it is not one.
H5Id OpenH5File(const std::string &path);

enum class ColumnKind { kInteger, kFloat };

struct ColumnSpec {
    const char *name;
    ColumnKind kind;
};

/// One value of a row as read: `i` for an integer column, `f` for a float column.
union H5Value {
    int64_t i;
    double f;
};

/// The table `name` of `file`: checked at construction to be a 1-D compound dataset holding every
/// column of `columns` with the kind given (a missing dataset, a missing field or a wrong class is
/// a DatasetError "FILE: table.field ...").
class H5Table {
  public:
    H5Table(const H5Id &file, std::string path, std::string name,
            const std::vector<ColumnSpec> &columns);
    [[nodiscard]] std::size_t rows() const { return rows_; }
    /// Rows [first, first + count) of every column given at construction, in one read: value k
    /// of row r at [r * columns + k] (integers converted to int64, floats to double).
    [[nodiscard]] std::vector<H5Value> Rows(std::size_t first, std::size_t count) const;
    /// Rows [first, first + count) of an integer column, converted to int64.
    [[nodiscard]] std::vector<int64_t> Integers(const char *column, std::size_t first,
                                                std::size_t count) const;
    /// Rows [first, first + count) of a float column, converted to double.
    [[nodiscard]] std::vector<double> Floats(const char *column, std::size_t first,
                                             std::size_t count) const;
    [[nodiscard]] std::string Where(const char *column) const;  ///< "FILE: table.column"

  private:
    void Read(const char *column, hid_t memory_type, std::size_t first, std::size_t count,
              void *out) const;

    std::string path_, name_;
    H5Id dataset_, space_, row_type_;  ///< row_type_: every column, 8 bytes each
    std::size_t columns_ = 0;
    std::size_t rows_ = 0;
};

}  // namespace dorado::io
