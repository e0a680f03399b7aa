#include "dorado/config/odometry_config.hpp"

#include <stdexcept>

#include "dorado/config/field_yaml.hpp"
#include "dorado/odometry/odometry_fields.hpp"

namespace dorado::config {
odometry::OdometryMethod ParseOdometryMethodKey(const std::string &text, const std::string &what) {
    try {
        return odometry::ParseOdometryMethod(text);
    } catch (const std::invalid_argument &e) {
        throw io::ConfigError(what + ": " + e.what());
    }
}

odometry::DopplerOdometryConfig LoadOdometryConfig(const std::string &yaml_path) {
    odometry::DopplerOdometryConfig config;
    FieldReader reader(io::YamlSection(io::LoadYamlFile(yaml_path), yaml_path));
    if (reader.Section("odometry").Has("rotation")) {
        throw io::ConfigError(
            yaml_path +
            ": key 'odometry.rotation' is now 'odometry.method' (doppler | imu "
            "| imu+doppler; the old 'imu' is 'imu+doppler', 'imu-only' is 'imu')");
    }
    if (reader.Section("ground").Has("base_height_m"))
        reader.Section("ground").Fail("base_height_m",
                                      "the base's height above the road is the vehicle's: the "
                                      "dataset's vehicle.base_height_m");
    VisitFields(config, reader);
    reader.RejectUnknownKeys();
    try {
        config.Validate();  // messages name the field as "section.key: ..."
    } catch (const std::invalid_argument &e) {
        throw KeyError(yaml_path, e);
    }
    return config;
}

std::string OdometryConfigYaml(const odometry::DopplerOdometryConfig &config) {
    odometry::DopplerOdometryConfig copy = config;
    FieldWriter writer;
    VisitFields(copy, writer);
    return writer.text();
}

std::vector<FieldRow> OdometryConfigFields() {
    return ListFields(odometry::DopplerOdometryConfig{});
}

}  // namespace dorado::config
