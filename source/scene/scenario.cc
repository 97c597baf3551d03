#include <suturesim/scene/scenario.h>

#include <stdexcept>

namespace suturesim::scene
{
  Scenario::Registry &
  Scenario::Registry::instance()
  {
    static Registry registry;
    return registry;
  }

  bool
  Scenario::Registry::add(Entry entry)
  {
    for (const auto &e : entries)
      if (e.name == entry.name)
        throw std::logic_error("scenario registered twice: " + entry.name);
    entries.push_back(std::move(entry));
    return true;
  }

  const Scenario::Entry *
  Scenario::Registry::find(const SceneParameters &scene) const
  {
    const Entry *found = nullptr;
    for (const auto &e : entries)
      if (e.applies(scene))
        {
          // two scenarios for one scene would make the choice depend on load order
          if (found != nullptr)
            throw std::logic_error("scenarios '" + found->name + "' and '" + e.name + "' both apply");
          found = &e;
        }
    return found;
  }
} // namespace suturesim::scene
