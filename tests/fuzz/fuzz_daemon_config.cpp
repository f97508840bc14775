// libFuzzer target: the services' configuration file (vifusiond.yaml, read by vifusiond and vifusion-health)
// on arbitrary text: loadYamlFile, whose errors name the file, then validate(), whose errors name the key (the
// command line can set it too). A file that is accepted must survive --dump-config: dumped, loaded and dumped
// again, the text is unchanged.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "vifusion/config/config_keys.hpp"
#include "vifusion/config/yaml_loader.hpp"

namespace {

using namespace vifusion;
using namespace vifusion::fuzz;

constexpr const char* kFileName = "vifusiond.yaml";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const ScratchFolder folder;
  const std::string path = folder.write(kFileName, std::span<const std::uint8_t>(data, size)).string();
  config::DaemonConfig loaded;
  if (!parsedOrNamedError({kFileName}, [&] { config::loadYamlFile(path, loaded); })) return 0;
  try {
    loaded.validate();
  } catch (const config::ConfigError& error) {
    require(std::string_view(error.what()).size() > 0);
    return 0;
  }
  const std::string dumped = config::dumpYaml(loaded);
  const std::string dumped_path =
      folder.write("dumped.yaml", std::span(reinterpret_cast<const std::uint8_t*>(dumped.data()), dumped.size()))
          .string();
  config::DaemonConfig reloaded;
  config::loadYamlFile(dumped_path, reloaded);
  reloaded.validate();
  require(config::dumpYaml(reloaded) == dumped);
  return 0;
}
