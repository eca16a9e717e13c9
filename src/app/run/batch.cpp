#include "app/run/batch.hpp"

#include "app/run/report.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/strings.hpp"
#include "core/timer.hpp"
#include "fracture/pattern_file.hpp"
#include "io/manifest.hpp"

#include <cstdlib>
#include <map>
#include <optional>
#include <regex>
#include <set>

namespace crackle::app {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t MAX_VARIANTS = 100000;

std::optional<std::uint64_t> whole_number(const std::string& text) {
    if (text.empty() || text.size() > 19 || text.find_first_not_of("0123456789") != std::string::npos)
        return std::nullopt;
    const std::uint64_t v = std::stoull(text);
    if (v > 9000000000000000000ULL) return std::nullopt;
    return v;
}

std::optional<std::int64_t> env_number(const char* name) {
    const char* v = std::getenv(name);
    if (!v || !*v) return std::nullopt;
    const auto n = whole_number(v);
    if (!n) throw InputError(std::string("$") + name, std::string("'") + v + "' is not a whole number", "unset it");
    return static_cast<std::int64_t>(*n);
}

/// A variant made ready: its preset resolved and planned, its names checked, its key computed.
/// The plan itself is made again when the variant bakes (a plan holds its variation images:
/// a thousand of them at once would not fit).
struct Prepared {
    const Variant* variant;
    io::Preset preset;
    std::string preset_name;
    std::uint64_t seed = 0;
    OutputPlan output; ///< the plan's names and maps
    OutputNames names;
    std::string key;
};

std::vector<Prepared> prepare(const std::vector<Variant>& variants, const BatchOptions& options) {
    std::vector<Prepared> out;
    out.reserve(variants.size());
    std::map<std::string, const Variant*> bases;
    for (const Variant& v : variants) {
        io::PresetRequest request = v.preset;
        request.overrides.insert(request.overrides.begin(), options.overrides.begin(), options.overrides.end());
        // The batch's --maps and --bit-depth sit under each variant's own set, --size over it.
        request =
            with_bake_flags(request, {options.size, options.maps, options.bit_depth, false, options.overrides.size()});
        try {
            io::Preset preset = io::load_preset(request);
            RunPlan plan = make_run_plan(preset, {.bake = true});
            BakeOutputs named = options.outputs;
            named.name_pattern = v.name.empty() ? "{preset}_{seed}" : v.name;
            named.name_where = v.where;
            OutputNames names = bake_names(plan, named, v.name, !v.name.empty());
            const std::string base = fs::path(names.base()).lexically_normal().string();
            if (const auto [at, fresh] = bases.emplace(base, &v); !fresh)
                throw InputError(v.where, "writes the same files as " + at->second->where + " ('" + base + "')",
                                 "give each variant its own name, or put {seed} or {variant} in the name");
            std::string fingerprint = std::string(crackle_version()) + "\n" + plan.record.settings.dump() + "\n" + base
                                      + "\n" + std::to_string(options.outputs.split_pieces);
            for (const std::string& m : options.outputs.meshes)
                fingerprint += "\nmesh " + m;
            out.push_back({&v, std::move(preset), plan.record.preset, plan.seed, std::move(plan.output),
                           std::move(names), hex64(fracture::fnv1a64(fingerprint))});
        } catch (const InputError& e) {
            if (v.where.empty() || std::string(e.what()).rfind(v.where, 0) == 0) throw;
            throw InputError(v.where + ": " + e.what());
        }
    }
    return out;
}

fs::path report_path(const BatchOptions& options, const Prepared& p) {
    return options.out_dir / (p.names.base() + ".json");
}

/// A variant is done when its report is on disk with its key (unless `any_key`: the merge, which
/// may run without the shards' options), and every file it lists is there.
bool finished(const BatchOptions& options, const Prepared& p, bool any_key = false) {
    const fs::path report = report_path(options, p);
    std::error_code ec;
    if (!fs::is_regular_file(report, ec)) return false;
    try {
        const Json j = Json::parse(read_file(report), report.string());
        const Json* key = j.find("variant_key");
        if (!key || (!any_key && key->as_string() != p.key)) return false;
        if (const Json* files = j.find("files"))
            for (const Json& f : files->elements())
                if (!fs::is_regular_file(f.as_string(), ec)) return false;
        return true;
    } catch (const InputError&) {
        return false;
    }
}

std::string shard_text(const Shard& s) {
    return std::to_string(s.index) + "/" + std::to_string(s.count);
}

fs::path summary_path(const BatchOptions& options) {
    return options.out_dir
           / ("batch-summary-" + std::to_string(options.shard.index) + "-of-" + std::to_string(options.shard.count)
              + ".json");
}

Json variant_entry(const Prepared& p, const std::string& status, const BatchOptions& options) {
    Json e = Json::object();
    e["index"] = p.variant->index;
    e["name"] = p.names.base();
    e["preset"] = p.preset_name;
    e["seed"] = static_cast<long long>(p.seed);
    e["status"] = status;
    e["report"] = report_path(options, p).string();
    return e;
}

/// Every file a variant writes (maps, meshes, its report).
std::vector<fs::path> expected_files(const BatchOptions& options, const Prepared& p) {
    std::vector<fs::path> files;
    for (const io::MapRequest& m : p.output.maps)
        files.push_back(p.names.map_file(options.out_dir, {m.name, "png", {}}));
    if (p.output.exr) files.push_back(p.names.map_file(options.out_dir, {"Displacement", "exr", {}}));
    for (const std::string& format : options.outputs.meshes)
        files.push_back(options.out_dir / (p.names.base() + "." + format));
    files.push_back(report_path(options, p));
    return files;
}

/// Temporary files a killed run left beside this shard's outputs ("<file>.tmp<pid>"). Only the
/// shard's own unfinished variants are cleaned: on a shared file system another shard's
/// temporaries are in use.
void remove_debris(const BatchOptions& options, const std::vector<const Prepared*>& unfinished,
                   const fs::path& summary) {
    std::map<fs::path, std::vector<fs::path>> temporaries; // final path → its temporaries
    std::error_code ec;
    const std::regex tmp(R"((.*)\.tmp[0-9]+)");
    for (auto it = fs::recursive_directory_iterator(options.out_dir, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        std::smatch m;
        const std::string path = it->path().string();
        if (std::regex_match(path, m, tmp)) temporaries[fs::path(m[1].str()).lexically_normal()].push_back(it->path());
    }
    if (temporaries.empty()) return;
    auto clean = [&](const fs::path& f) {
        if (const auto at = temporaries.find(f.lexically_normal()); at != temporaries.end())
            for (const fs::path& t : at->second) {
                fs::remove(t, ec);
                log::info("removed ", t.string(), ", left by an interrupted run");
            }
    };
    clean(summary);
    for (const Prepared* p : unfinished)
        for (const fs::path& f : expected_files(options, *p))
            clean(f);
}

} // namespace

std::vector<std::uint64_t> parse_seed_list(const std::string& text, const std::string& where) {
    const std::string fix = "write seeds as whole numbers 0…9000000000000000000, ranges and lists: 1-100 or 1,5,9-12";
    std::vector<std::uint64_t> seeds;
    for (const std::string& raw : split(text, ',')) {
        const std::string item = trim(raw);
        const auto dash = item.find('-', 1);
        const auto first = whole_number(item.substr(0, dash));
        const auto last = dash == std::string::npos ? first : whole_number(item.substr(dash + 1));
        if (!first || !last) throw InputError(where, "'" + item + "' is not a seed or a range of seeds", fix);
        if (*last < *first) throw InputError(where, "the range '" + item + "' runs backwards", fix);
        if (*last - *first >= MAX_VARIANTS || seeds.size() + (*last - *first) >= MAX_VARIANTS)
            throw InputError(where, "more than 100000 seeds", "split the batch into several runs");
        for (std::uint64_t s = *first; s <= *last; ++s)
            seeds.push_back(s);
    }
    if (seeds.empty()) throw InputError(where, "no seeds", fix);
    return seeds;
}

Shard resolve_shard(const std::string& flag) {
    Shard s;
    const std::string fix = "give --shard i/N with 1 ≤ i ≤ N (e.g. --shard 3/10), or run under a Slurm job array "
                            "or a Kubernetes Indexed Job (docs/farm.md)";
    std::optional<std::int64_t> count;
    if (!flag.empty()) {
        const auto slash = flag.find('/');
        const auto n = whole_number(slash == std::string::npos ? flag : flag.substr(slash + 1));
        if (!n || *n < 1 || *n > MAX_VARIANTS) throw InputError("--shard " + flag, "not a shard", fix);
        count = static_cast<std::int64_t>(*n);
        if (slash != std::string::npos) {
            const auto i = whole_number(flag.substr(0, slash));
            if (!i || *i < 1 || *i > *n) throw InputError("--shard " + flag, "the shard number is not in 1…N", fix);
            return Shard{static_cast<int>(*i), static_cast<int>(*n), "--shard"};
        }
    }
    if (const auto id = env_number("SLURM_ARRAY_TASK_ID")) {
        const std::int64_t min = env_number("SLURM_ARRAY_TASK_MIN").value_or(0);
        const auto n = env_number("SLURM_ARRAY_TASK_COUNT");
        if (!n && !count)
            throw InputError("$SLURM_ARRAY_TASK_ID", "a Slurm array task without SLURM_ARRAY_TASK_COUNT", fix);
        s = Shard{static_cast<int>(*id - min + 1), static_cast<int>(n.value_or(*count)), "SLURM_ARRAY_TASK_ID"};
    } else if (const auto k8s = env_number("JOB_COMPLETION_INDEX")) {
        const auto n = count ? count : env_number("CRACKLE_SHARD_COUNT");
        if (!n)
            throw InputError("$JOB_COMPLETION_INDEX", "an indexed Job without a shard count",
                             "pass --shard N (the Job's completions) or set CRACKLE_SHARD_COUNT");
        s = Shard{static_cast<int>(*k8s + 1), static_cast<int>(*n), "JOB_COMPLETION_INDEX"};
    } else if (count) {
        throw InputError("--shard " + flag, "a shard count without a shard number",
                         "write --shard i/N, or run under Slurm or Kubernetes, which give the number");
    }
    if (s.count < 1 || s.index < 1 || s.index > s.count)
        throw InputError("$" + s.source, "shard " + shard_text(s) + " is out of range",
                         "use a contiguous array 0…N−1 (Slurm --array=0-" + std::to_string(s.count - 1)
                             + ", Kubernetes completions = N)");
    return s;
}

std::vector<Variant> read_manifest(const fs::path& path) {
    std::vector<Variant> variants;
    for (const io::ManifestEntry& e : io::read_manifest_entries(path)) {
        std::vector<std::int64_t> seeds = {e.seed};
        if (!e.seeds.empty()) {
            seeds.clear();
            for (const std::uint64_t s : parse_seed_list(e.seeds, e.where))
                seeds.push_back(static_cast<std::int64_t>(s));
        }
        for (const std::int64_t seed : seeds) {
            if (variants.size() >= MAX_VARIANTS)
                throw InputError(path.string(), "more than 100000 variants", "split the manifest");
            Variant v;
            v.index = variants.size();
            v.preset = io::PresetRequest{e.preset, e.overrides, seed, {}};
            v.name = e.name;
            v.where = e.where;
            variants.push_back(std::move(v));
        }
    }
    return variants;
}

int run_batch(const std::vector<Variant>& variants, const BatchOptions& options, const GlobalOptions& global,
              std::ostream& out) {
    Timer total;
    const std::vector<Prepared> all = prepare(variants, options); // everything checked before any work
    std::vector<const Prepared*> mine;
    for (const Prepared& p : all)
        if (options.shard.contains(p.variant->index)) mine.push_back(&p);

    Json summary = Json::object();
    summary["crackle_version"] = crackle_version();
    summary["manifest"] = options.manifest;
    summary["shard"] = shard_text(options.shard);
    summary["shard_source"] = options.shard.source;
    summary["variants_total"] = all.size();
    summary["variants_in_shard"] = mine.size();
    std::vector<const Prepared*> unfinished;
    for (const Prepared* p : mine)
        if (!finished(options, *p)) unfinished.push_back(p);
    remove_debris(options, unfinished, summary_path(options));
    Json entries = Json::array();
    int code = 0;
    std::size_t done = 0, skipped = 0, failed = 0;
    auto write_summary = [&] {
        Json s = summary;
        s["done"] = done;
        s["skipped"] = skipped;
        s["failed"] = failed;
        s["wall_seconds"] = total.seconds();
        s["variants"] = entries;
        write_file_atomically(summary_path(options), s.dump());
    };
    if (!global.quiet)
        out << "crackle batch: shard " << shard_text(options.shard) << " (" << options.shard.source
            << "): " << mine.size() << " of " << all.size() << " variants into " << options.out_dir.string() << "/\n";
    for (std::size_t k = 0; k < mine.size(); ++k) {
        const Prepared& p = *mine[k];
        const std::string tag =
            "  [" + std::to_string(k + 1) + "/" + std::to_string(mine.size()) + "] " + p.names.base();
        if (finished(options, p)) {
            ++skipped;
            entries.push_back(variant_entry(p, "skipped", options));
            if (!global.quiet) out << tag << ": already done\n";
            continue;
        }
        Timer step;
        Json entry = variant_entry(p, "done", options);
        try {
            BakeOutputs outputs = options.outputs;
            outputs.dir = options.out_dir;
            outputs.report_beside = true;
            outputs.variant_key = p.key;
            StepTimes times;
            const Json report = bake_one(make_run_plan(p.preset, {.bake = true}), outputs, p.names, options.shader_dir,
                                         options.pattern, times);
            ++done;
            entry["pattern_source"] = *report.find("pattern_source");
            if (!global.quiet)
                out << tag << ": done in " << fmt("%.1f", step.seconds()) << " s (pattern "
                    << report.find("pattern_source")->as_string() << ")\n";
        } catch (const std::exception& e) {
            // One failed variant does not stop the shard; the exit code says the worst.
            const int c = dynamic_cast<const InputError*>(&e) ? 2 : dynamic_cast<const NumericError*>(&e) ? 3 : 1;
            code = std::max(code, c);
            ++failed;
            entry["status"] = "failed";
            entry["exit_code"] = c;
            entry["error"] = std::string(e.what());
            log::error(p.variant->where.empty() ? p.names.base() : p.variant->where, ": ", e.what());
        }
        entry["seconds"] = step.seconds();
        entries.push_back(entry);
        write_summary(); // after every variant: a killed shard still says how far it got
    }
    write_summary();
    if (!global.quiet)
        out << "  " << done << " baked, " << skipped << " already done, " << failed << " failed in "
            << fmt("%.1f", total.seconds()) << " s; summary " << summary_path(options).string() << "\n";
    return code;
}

int list_batch(const std::vector<Variant>& variants, const BatchOptions& options, std::ostream& out) {
    for (const Prepared& p : prepare(variants, options))
        if (options.shard.contains(p.variant->index))
            out << p.variant->index << "\t" << p.names.base() << "\t" << p.preset_name << "\t" << p.seed << "\n";
    return 0;
}

int merge_batch(const std::vector<Variant>& variants, const BatchOptions& options, std::ostream& out) {
    const std::vector<Prepared> all = prepare(variants, options);
    // Which shards baked (or, rerun, found done) which variant: exactly one each.
    std::map<std::size_t, std::set<std::string>> claims;
    std::size_t summaries = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(options.out_dir, ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("batch-summary-", 0) != 0 || e.path().extension() != ".json") continue;
        ++summaries;
        const Json s = Json::parse(read_file(e.path()), e.path().string());
        for (const Json& v : s.find("variants") ? s.find("variants")->elements() : Json::Array{})
            if (const Json* st = v.find("status"); st && st->as_string() != "failed")
                claims[static_cast<std::size_t>(v.find("index")->as_number())].insert(s.find("shard")->as_string());
    }
    Json entries = Json::array();
    std::size_t done = 0;
    std::vector<std::string> problems;
    for (const Prepared& p : all) {
        const bool ok = finished(options, p, true);
        const auto& by = claims[p.variant->index];
        Json e = variant_entry(p, ok ? "done" : "missing", options);
        Json shards = Json::array();
        for (const std::string& s : by)
            shards.push_back(s);
        e["shards"] = shards;
        entries.push_back(e);
        if (ok) ++done;
        if (!ok) problems.push_back(p.names.base() + " (" + p.variant->where + ") has no finished report");
        if (by.size() > 1)
            problems.push_back(p.names.base() + " was baked by more than one shard (overlapping shards?)");
    }
    Json merged = Json::object();
    merged["crackle_version"] = crackle_version();
    merged["manifest"] = options.manifest;
    merged["shard_summaries"] = summaries;
    merged["variants_total"] = all.size();
    merged["done"] = done;
    merged["missing"] = all.size() - done;
    merged["variants"] = entries;
    write_file_atomically(options.out_dir / "batch-summary.json", merged.dump());
    out << "crackle batch --merge: " << done << " of " << all.size() << " variants done (" << summaries
        << " shard summaries); " << (options.out_dir / "batch-summary.json").string() << "\n";
    for (std::size_t i = 0; i < problems.size() && i < 20; ++i)
        out << "  missing: " << problems[i] << "\n";
    if (problems.size() > 20) out << "  ... and " << problems.size() - 20 << " more\n";
    return problems.empty() ? 0 : 1;
}

} // namespace crackle::app
