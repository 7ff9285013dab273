#include "coupling/momentum_exchange.h"

namespace lbsolid::coupling {

const char* exchange_rule_name(ExchangeRule rule) {
  switch (rule) {
    case ExchangeRule::kCommonVelocity: return "common-velocity";
    case ExchangeRule::kPairwise: return "pairwise";
  }
  return "?";
}

}  // namespace lbsolid::coupling
