#include "pbd/constraints/constraint_families.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <tuple>
#include <type_traits>
#include <utility>

namespace pbd {
namespace {

template <typename T>
struct IsVector : std::false_type {};
template <typename T>
struct IsVector<std::vector<T>> : std::true_type {};

template <typename T, typename = void>
struct HasParticleArray : std::false_type {};
template <typename T>
struct HasParticleArray<T, std::void_t<decltype(std::declval<const T&>().particles.size())>>
    : std::true_type {};

/// The particles an element couples (the seed's Constraint::m_bodies); only the cloth and solid
/// families are asked.
template <typename T>
std::vector<int> elementParticles(const T& c) {
  if constexpr (std::is_same_v<T, ParticleDistanceConstraint>)
    return {c.particle1, c.particle2};
  else if constexpr (HasParticleArray<T>::value)
    return std::vector<int>(c.particles.begin(), c.particles.end());
  else
    return {};
}

/// Whether a family's elements come after the model's first group of elements in the seed's
/// list: the bending of a triangle model (after its cloth elements), the volumes of a tet model
/// (after its edges).
bool secondInItsModel(int family) {
  return family == 4 /* tetVolumes */ || family == 8 /* clothBending */ ||
         family == 9 /* clothDihedrals */;
}

}  // namespace

ConstraintFamilies ConstraintFamilies::fromScene(const Scene& scene) {
  ConstraintFamilies families;
  families.forEachFamily([&](auto& array, const auto& build, const auto&) {
    if constexpr (!std::is_same_v<std::decay_t<decltype(build)>, AddedInCpp>) array = build(scene);
  });
  return families;
}

void ConstraintFamilies::solvePositions(BodyStates& bodies, Real substepSize, bool firstIteration) {
  int family = 0;
  forEachFamily([&](auto& array, const auto&, const auto& sweep) {
    const int index = family++;
    const bool seedOrdered =
        !seedOrder.empty() && index >= kFirstSeedOrdered && index <= kLastSeedOrdered;
    if (!seedOrdered) {
      sweep(array, bodies, substepSize, firstIteration, 0, SIZE_MAX);
      return;
    }
    if (index != kFirstSeedOrdered) return;  // every seed-ordered family runs from here
    for (const SeedRun& run : seedOrder) {
      int other = 0;
      forEachFamily([&](auto& runArray, const auto&, const auto& runSweep) {
        if (other++ == run.family)
          runSweep(runArray, bodies, substepSize, firstIteration, run.begin, run.end);
      });
    }
  });
}

void ConstraintFamilies::orderAsTheSeed(const Scene& scene) {
  orderRodsAsTheSeed(rods);
  // The model of every particle: triangle models first, then tet models (the seed's order).
  std::vector<int> modelOf(scene.particles.size(), -1);
  int model = 0;
  const auto mark = [&](int first, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i)
      if (std::size_t(first) + i < modelOf.size()) modelOf[std::size_t(first) + i] = model;
    ++model;
  };
  for (const TriangleModelDesc& m : scene.triangleModels)
    mark(m.firstParticle, m.mesh.vertices.size());
  for (const TetModelDesc& m : scene.tetModels)
    mark(m.firstParticle, m.mesh.vertices.size());

  struct Element {
    int family = 0;
    std::size_t index = 0;
    std::tuple<int, int, int, std::size_t> seedKey;  ///< model, phase, family, index
    std::vector<int> particles;
    std::size_t group = 0;
  };
  std::vector<Element> elements;
  int family = 0;
  forEachFamily([&](auto& array, const auto&, const auto&) {
    const int index = family++;
    if (index < kFirstSeedOrdered || index > kLastSeedOrdered) return;
    if constexpr (IsVector<std::decay_t<decltype(array)>>::value) {
      for (std::size_t k = 0; k < array.size(); ++k) {
        Element e;
        e.family = index;
        e.index = k;
        e.particles = elementParticles(array[k]);
        const int first = e.particles.empty() ? -1 : e.particles[0];
        const int owner =
            first >= 0 && std::size_t(first) < modelOf.size() ? modelOf[std::size_t(first)] : model;
        e.seedKey = std::make_tuple(owner, secondInItsModel(index) ? 1 : 0, index, k);
        elements.push_back(std::move(e));
      }
    }
  });
  std::stable_sort(elements.begin(), elements.end(),
                   [](const Element& a, const Element& b) { return a.seedKey < b.seedKey; });

  // Greedy colouring in list order: the first group none of whose particles it touches.
  std::vector<std::vector<char>> used;
  for (Element& e : elements) {
    std::size_t g = 0;
    for (; g < used.size(); ++g) {
      bool free = true;
      for (int p : e.particles)
        if (used[g][std::size_t(p)]) {
          free = false;
          break;
        }
      if (free) break;
    }
    if (g == used.size()) used.emplace_back(scene.particles.size(), char(0));
    for (int p : e.particles)
      used[g][std::size_t(p)] = 1;
    e.group = g;
  }
  std::stable_sort(elements.begin(), elements.end(),
                   [](const Element& a, const Element& b) { return a.group < b.group; });

  // Permute every family into that order and record the runs.
  std::array<std::vector<std::size_t>, kLastSeedOrdered + 1> newOrder;
  seedOrder.clear();
  std::array<std::size_t, kLastSeedOrdered + 1> placed{};
  for (const Element& e : elements) {
    newOrder[std::size_t(e.family)].push_back(e.index);
    const std::size_t position = placed[std::size_t(e.family)]++;
    if (!seedOrder.empty() && seedOrder.back().family == e.family &&
        seedOrder.back().end == position)
      ++seedOrder.back().end;
    else
      seedOrder.push_back({e.family, position, position + 1});
  }
  family = 0;
  forEachFamily([&](auto& array, const auto&, const auto&) {
    const int index = family++;
    if (index < kFirstSeedOrdered || index > kLastSeedOrdered) return;
    if constexpr (IsVector<std::decay_t<decltype(array)>>::value) {
      std::decay_t<decltype(array)> permuted;
      permuted.reserve(array.size());
      for (std::size_t k : newOrder[std::size_t(index)])
        permuted.push_back(array[k]);
      array = std::move(permuted);
    }
  });
}

}  // namespace pbd
