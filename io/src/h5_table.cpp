#include "h5_table.hpp"

#include <algorithm>
#include <utility>

#include "dorado/io/dataset.hpp"

namespace dorado::io {

namespace {

// HDF5 prints its error stack to stderr by default: the errors here are ours, naming the file.
void SilenceHdf5() {
    static const bool silenced = [] { return H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr) >= 0; }();
    (void)silenced;
}

const char *ClassName(H5T_class_t c) {
    switch (c) {
        case H5T_INTEGER:
            return "an integer";
        case H5T_FLOAT:
            return "a float";
        case H5T_STRING:
            return "a string";
        case H5T_COMPOUND:
            return "a compound";
        default:
            return "a non-numeric";
    }
}

std::string MemberNames(hid_t type) {
    std::string names;
    const int n = H5Tget_nmembers(type);
    for (int i = 0; i < n; ++i) {
        char *name = H5Tget_member_name(type, static_cast<unsigned>(i));
        names += (names.empty() ? "" : ", ") + std::string(name ? name : "?");
        H5free_memory(name);
    }
    return names.empty() ? "(none)" : names;
}

}  // namespace

H5Id &H5Id::operator=(H5Id &&other) noexcept {
    std::swap(id_, other.id_);
    std::swap(close_, other.close_);
    return *this;
}

H5Id::~H5Id() {
    if (id_ >= 0 && close_ != nullptr) close_(id_);
}

H5Id OpenH5File(const std::string &path) {
    SilenceHdf5();
    H5Id file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.valid())
        throw DatasetError(path +
                           ": cannot open as an HDF5 file (missing, truncated or another "
                           "format)");
    return file;
}

H5Table::H5Table(const H5Id &file, std::string path, std::string name,
                 const std::vector<ColumnSpec> &columns)
    : path_(std::move(path)), name_(std::move(name)) {
    if (H5Lexists(file.get(), name_.c_str(), H5P_DEFAULT) <= 0)
        throw DatasetError(path_ + ": no dataset '" + name_ + "'");
    dataset_ = H5Id(H5Dopen2(file.get(), name_.c_str(), H5P_DEFAULT), H5Dclose);
    if (!dataset_.valid()) throw DatasetError(path_ + ": cannot open dataset '" + name_ + "'");
    const H5Id type(H5Dget_type(dataset_.get()), H5Tclose);
    if (H5Tget_class(type.get()) != H5T_COMPOUND)
        throw DatasetError(path_ + ": dataset '" + name_ + "' is not a table of compound rows");
    space_ = H5Id(H5Dget_space(dataset_.get()), H5Sclose);
    hsize_t dims[1] = {0};
    if (H5Sget_simple_extent_ndims(space_.get()) != 1 ||
        H5Sget_simple_extent_dims(space_.get(), dims, nullptr) != 1)
        throw DatasetError(path_ + ": dataset '" + name_ + "' is not one-dimensional");
    rows_ = static_cast<std::size_t>(dims[0]);
    for (const ColumnSpec &column : columns) {
        const int index = H5Tget_member_index(type.get(), column.name);
        if (index < 0)
            throw DatasetError(Where(column.name) +
                               ": no such field (fields: " + MemberNames(type.get()) + ")");
        const H5T_class_t found = H5Tget_member_class(type.get(), static_cast<unsigned>(index));
        const H5T_class_t wanted = column.kind == ColumnKind::kInteger ? H5T_INTEGER : H5T_FLOAT;
        if (found != wanted)
            throw DatasetError(Where(column.name) + ": " + ClassName(found) + " field, expected " +
                               ClassName(wanted));
    }
    // The memory layout of Rows(): HDF5 converts each member from the file's type by name.
    columns_ = columns.size();
    row_type_ = H5Id(H5Tcreate(H5T_COMPOUND, std::max<std::size_t>(1, columns_) * 8), H5Tclose);
    for (std::size_t k = 0; k < columns_; ++k) {
        H5Tinsert(row_type_.get(), columns[k].name, 8 * k,
                  columns[k].kind == ColumnKind::kInteger ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE);
    }
}

std::vector<H5Value> H5Table::Rows(std::size_t first, std::size_t count) const {
    std::vector<H5Value> values(count * columns_);
    Read("*", row_type_.get(), first, count, values.data());
    return values;
}

std::string H5Table::Where(const char *column) const {
    return path_ + ": " + name_ + "." + column;
}

void H5Table::Read(const char *column, hid_t memory_type, std::size_t first, std::size_t count,
                   void *out) const {
    if (count == 0) return;
    if (first + count > rows_)
        throw DatasetError(Where(column) + ": rows " + std::to_string(first) + ".." +
                           std::to_string(first + count) + " beyond its " + std::to_string(rows_) +
                           " rows");
    const H5Id file_space(H5Scopy(space_.get()), H5Sclose);
    const hsize_t start[1] = {first}, n[1] = {count};
    H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, n, nullptr);
    const H5Id memory_space(H5Screate_simple(1, n, nullptr), H5Sclose);
    if (H5Dread(dataset_.get(), memory_type, memory_space.get(), file_space.get(), H5P_DEFAULT,
                out) < 0)
        throw DatasetError(Where(column) + ": cannot read rows " + std::to_string(first) + ".." +
                           std::to_string(first + count) + " (a truncated file?)");
}

namespace {

// One member of the compound row, converted by HDF5 from the file's type to `native`.
H5Id MemberType(const char *column, hid_t native, std::size_t size) {
    H5Id type(H5Tcreate(H5T_COMPOUND, size), H5Tclose);
    H5Tinsert(type.get(), column, 0, native);
    return type;
}

}  // namespace

std::vector<int64_t> H5Table::Integers(const char *column, std::size_t first,
                                       std::size_t count) const {
    std::vector<int64_t> values(count);
    const H5Id type = MemberType(column, H5T_NATIVE_INT64, sizeof(int64_t));
    Read(column, type.get(), first, count, values.data());
    return values;
}

std::vector<double> H5Table::Floats(const char *column, std::size_t first,
                                    std::size_t count) const {
    std::vector<double> values(count);
    const H5Id type = MemberType(column, H5T_NATIVE_DOUBLE, sizeof(double));
    Read(column, type.get(), first, count, values.data());
    return values;
}

}  // namespace dorado::io
