#pragma once
/// @file Batches (docs/farm.md): many variants of presets, overrides and seeds, baked in slices
/// (shards) that existing schedulers run in parallel (a Slurm job array, a Kubernetes Indexed
/// Job), with no scheduler of our own.
///
/// Variant k (0-based, manifest order) belongs to shard (k mod N) + 1 of N: round robin, so a
/// manifest sorted by preset spreads each preset's cost over every shard. A variant is done
/// when its report <base>.json is on disk with the same variant key (the report is written
/// last and atomically, so a killed run leaves no report for a half-written set); a rerun skips
/// done variants and redoes the rest. Each shard writes batch-summary-<i>-of-<N>.json; `batch
/// --merge` combines them and checks that every variant is done exactly once.

#include "app/commands/global_options.hpp"
#include "app/run/bake_run.hpp"
#include "io/preset.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace crackle::app {

struct Variant {
    std::size_t index = 0;    ///< position in the manifest (0-based)
    io::PresetRequest preset; ///< name, overrides and seed (−1 = the preset's own)
    std::string name;         ///< the manifest's name pattern ("" = bake.name or {preset}_{seed})
    std::string where;        ///< "manifest.jsonl:12", for messages
};

/// Shard i of N, 1-based.
struct Shard {
    int index = 1, count = 1;
    std::string source = "default"; ///< "--shard", "SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"
    bool contains(std::size_t variant) const { return static_cast<int>(variant % std::size_t(count)) + 1 == index; }
};

/// "1-100", "1,5,9-12" → the seeds in order. Throws InputError naming `where` for anything else,
/// a descending range, or more than 100 000 seeds.
std::vector<std::uint64_t> parse_seed_list(const std::string& text, const std::string& where);

/// The shard to run: `--shard i/N` when given; else Slurm's SLURM_ARRAY_TASK_ID (minus
/// SLURM_ARRAY_TASK_MIN) of SLURM_ARRAY_TASK_COUNT; else Kubernetes' JOB_COMPLETION_INDEX with
/// N from `--shard N` or CRACKLE_SHARD_COUNT; else 1/1. Throws InputError when they disagree or
/// are out of range.
Shard resolve_shard(const std::string& flag);

/// Reads a manifest: JSON Lines (.jsonl, .ndjson: one {"preset", "seed", "name", "set"} object
/// per line) or TOML (.toml: [[variant]] tables with the same keys; `seeds = "1-10"` expands a
/// variant over a seed list in either). Throws InputError with file:line.
std::vector<Variant> read_manifest(const std::filesystem::path& path);

/// The options every variant of a batch shares (from the command line).
struct BatchOptions {
    std::filesystem::path out_dir = "out";
    std::vector<std::string> overrides; ///< applied before each variant's own "set"
    std::string maps, bit_depth;        ///< --maps, --bit-depth: under each variant's own "set"
    std::string size;                   ///< --size, as in bake (over each variant's own "set")
    BakeOutputs outputs;                ///< meshes, pieces (the names come per variant)
    std::string shader_dir;
    PatternOptions pattern;
    Shard shard;
    std::string manifest; ///< for the summary ("" = a seed list)
};

/// Runs the shard's variants, skipping finished ones; writes the shard's summary. Every variant
/// is checked (preset, names, no two variants writing the same files) before any work. Returns
/// 0 when all of the shard's variants are done, else the exit code of the worst failure.
int run_batch(const std::vector<Variant>& variants, const BatchOptions& options, const GlobalOptions& global,
              std::ostream& out);

/// Prints the shard's variants, one per line: index, base name, preset, seed (nothing baked).
int list_batch(const std::vector<Variant>& variants, const BatchOptions& options, std::ostream& out);

/// Merges the shard summaries in options.out_dir into batch-summary.json and checks every
/// variant against its report on disk (the report and every file it lists; not the variant key,
/// so the merge needs none of the shards' --set or --size): 0 when all are done and each by one
/// shard, 1 (with the list) otherwise.
int merge_batch(const std::vector<Variant>& variants, const BatchOptions& options, std::ostream& out);

} // namespace crackle::app
