#pragma once
/**
 * @file
 * A scene file read into a dealii::ParameterHandler, with the bookkeeping that lets every
 * later check name the file, the line and the parameter of a bad value.
 */

#include <deal.II/base/parameter_handler.h>

#include <Eigen/Core>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace suturesim
{
  class ParameterFile
  {
  public:
    /// Reads @p text (the scene file's content, called @p name in messages) into @p prm,
    /// which must hold every declaration already, then the command-line overrides
    /// @p command_line ("Sub/Key=value" each, see apply_override()). Parse errors of
    /// deal.II (syntax, unknown key or subsection, wrong type, out-of-range value) become
    /// one-line InputErrors "name:line: ...". @p directory resolves relative paths.
    ///
    /// **Model sections.** A top-level block "subsection Model <path> ... end" holds
    /// settings of one model path only (e.g. the accurate path's mesh, time step and
    /// penalties, which differ from the realtime path's for the same scene): it is read
    /// when Model = <path> (from the file or the command line), over the rest of the
    /// file, and the command line goes over both. Its body is written like the file
    /// itself (subsections and "set" lines); it cannot set Model. The text outside any
    /// model section is common to all paths, so one scene file runs in every path at
    /// each path's own resolution. On the command line, "Model <path>/Sub/Key=value" is a
    /// setting of that section, as if written there: read in that path only, under the
    /// plain overrides (a study coarsens the accurate reference this way and leaves the
    /// realtime cases alone; a case's own plain setting still wins).
    ParameterFile(dealii::ParameterHandler       &prm,
                  const std::string              &text,
                  const std::string              &name,
                  const std::string              &directory,
                  const std::vector<std::string> &command_line = {});

    /// Reads the file @p file_name; a missing or unreadable file is an InputError.
    static ParameterFile
    from_file(dealii::ParameterHandler       &prm,
              const std::string              &file_name,
              const std::vector<std::string> &command_line = {});

    /// Applies a command-line override "Sub/Sub/Key=value"; a bad one is an InputError
    /// naming the override.
    void
    apply_override(dealii::ParameterHandler &prm, const std::string &assignment);

    /// The line of "Sub/Sub/Key" in the file, 0 when it is not set there (default).
    int
    line_of(const std::string &path) const;

    /// Whether "Sub/Sub/Key" is set in the file or by a command-line override (not left
    /// at its default): what a setting that fixes others (a suture preset) must respect.
    bool
    given(const std::string &path) const;

    /// Throws InputError "file:line: path: problem" (the line is omitted for defaults,
    /// and "--set" is named for command-line overrides).
    [[noreturn]] void
    fail(const std::string &path, const std::string &problem) const;

    /// A path relative to the scene file's directory, else to the suturesim source tree
    /// (meshes/ and parameters/ of the project); absolute paths are kept.
    std::string
    resolve(const std::string &path) const;

    const std::string &
    name() const
    {
      return file_name;
    }

  private:
    /// Parses @p text (the file's line count) into @p prm; errors name this file.
    void
    parse(dealii::ParameterHandler &prm, const std::string &text) const;

    /// Sets "Sub/Key=value" in @p prm and returns the path "Sub/Key".
    static std::string
    set_path(dealii::ParameterHandler &prm, const std::string &assignment);

    std::string                file_name;
    std::string                directory;
    std::map<std::string, int> lines;
    std::vector<std::string>   overrides;
  };

  /// A view of one subsection of a ParameterFile, for the checks a class makes on its
  /// own parameters after parsing them.
  /// @p relative inside the suturesim source tree (meshes/, parameters/, postprocess/).
  std::string
  project_path(const std::string &relative);

  class ParameterScope
  {
  public:
    ParameterScope(const ParameterFile &file, std::string path)
      : file(&file)
      , path(std::move(path))
    {}

    ParameterScope
    subsection(const std::string &name) const
    {
      return ParameterScope(*file, path.empty() ? name : path + "/" + name);
    }

    /// Throws an InputError naming file, line and this scope's @p key.
    [[noreturn]] void
    fail(const std::string &key, const std::string &problem) const
    {
      file->fail(path.empty() ? key : path + "/" + key, problem);
    }

    /// Throws unless @p condition holds.
    void
    require(const bool condition, const std::string &key, const std::string &problem) const
    {
      if (!condition)
        fail(key, problem);
    }

    const ParameterFile &
    parameter_file() const
    {
      return *file;
    }

  private:
    const ParameterFile *file;
    std::string          path;
  };

  /// The pattern of a 3-vector entry "x, y, z".
  const dealii::Patterns::List &
  vector_pattern();

  /// Reads the 3-vector entry @p key of the current subsection.
  Eigen::Vector3d
  get_vector(const dealii::ParameterHandler &prm, const std::string &key);

  /// Reads a map entry @p key, "name: v, v, ...; name: ...", in its order; names trimmed.
  std::vector<std::pair<std::string, std::vector<double>>>
  get_named_values(const dealii::ParameterHandler &prm, const std::string &key);

  /// Reads a map entry @p key of named points, "name: x, y, z; ...", in the file's order
  /// (a std::map would sort them and merge duplicates silently); a point without a
  /// name, without three coordinates or named twice fails through @p scope, calling it a
  /// @p noun ("probe", "access point").
  std::vector<std::pair<std::string, Eigen::Vector3d>>
  get_named_points(const dealii::ParameterHandler &prm, const std::string &key, const ParameterScope &scope,
                   const std::string &noun);

  /// Reads the keyframe entry @p key, "t: v, v, ...; t: ...", into time → values; a time
  /// given twice fails through @p scope. Value counts are the caller's to check.
  std::map<double, std::vector<double>>
  get_keyframes(const dealii::ParameterHandler &prm, const std::string &key, const ParameterScope &scope);
} // namespace suturesim
