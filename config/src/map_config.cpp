#include "dorado/config/map_config.hpp"

#include <stdexcept>

#include "dorado/config/field_yaml.hpp"
#include "dorado/mapping/mapper_fields.hpp"

namespace dorado::config {
mapping::PriorKind ParsePriorKindKey(const std::string &text, const std::string &what) {
    try {
        return mapping::ParsePriorKind(text);
    } catch (const std::invalid_argument &e) {
        throw io::ConfigError(what + ": " + e.what());
    }
}

MapCommandConfig LoadMapConfig(const std::string &yaml_path) {
    MapCommandConfig config;
    FieldReader reader(io::YamlSection(io::LoadYamlFile(yaml_path), yaml_path));
    VisitFields(config, reader);
    reader.RejectUnknownKeys();
    try {
        config.mapper.Validate();
        config.prior.Validate();
        config.loop_closure.Validate();
    } catch (const std::invalid_argument &e) {
        throw KeyError(yaml_path, e);
    }
    return config;
}

std::string MapConfigYaml(const MapCommandConfig &config) {
    MapCommandConfig copy = config;
    FieldWriter writer;
    VisitFields(copy, writer);
    return writer.text();
}

std::vector<FieldRow> MapConfigFields() {
    return ListFields(MapCommandConfig{});
}

}  // namespace dorado::config
