#pragma once
// The design as JSON, for the results file's header, which carries the design it was run with.
#include "../base/json_node.hpp"
#include "vaw/trials/design.hpp"

namespace vaw::trials::detail_json {

Design designFromNode(const vaw::detail::Node& root);
vaw::detail::Json designToJson(const Design& d);

}  // namespace vaw::trials::detail_json
