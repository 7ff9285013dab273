#include "fluid/population_block_advice.h"

#include <atomic>

namespace lbsolid::fluid {
namespace {
std::atomic<PopulationBlockAdvice> advice{nullptr};
}  // namespace

void set_population_block_advice(PopulationBlockAdvice a) { advice.store(a, std::memory_order_release); }

PopulationBlockAdvice population_block_advice() { return advice.load(std::memory_order_acquire); }

}  // namespace lbsolid::fluid
