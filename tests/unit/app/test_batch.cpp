// Batches (issue 14): seed lists, output names, manifests, shards (and the Slurm and Kubernetes
// files in docs/farm/ that drive them), idempotent reruns after a kill -9, and the merge.
#include "app/run/batch.hpp"
#include "app/run/naming.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"
#include "io/png.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

#include <chrono>
#include <csignal>
#include <regex>
#include <set>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace crackle;
using test::run_cli;
namespace fs = std::filesystem;

namespace {

/// Sets or clears environment variables for one scope.
class Env {
public:
    Env(std::initializer_list<std::pair<const char*, const char*>> vars) {
        for (const auto& [name, value] : vars) {
            const char* old = std::getenv(name);
            m_old.emplace_back(name, old ? std::optional<std::string>(old) : std::nullopt);
            if (value)
                setenv(name, value, 1);
            else
                unsetenv(name);
        }
    }
    ~Env() {
        for (const auto& [name, old] : m_old)
            if (old)
                setenv(name, old->c_str(), 1);
            else
                unsetenv(name);
    }

private:
    std::vector<std::pair<const char*, std::optional<std::string>>> m_old;
};

std::vector<std::size_t> indices_of(const std::string& listing) {
    std::vector<std::size_t> out;
    std::istringstream in(listing);
    std::string line;
    while (std::getline(in, line))
        if (!line.empty()) out.push_back(std::stoul(line.substr(0, line.find('\t'))));
    return out;
}

std::string shell(const std::string& cmd) {
    std::string out;
    FILE* pipe = popen((cmd + " 2>&1").c_str(), "r");
    char buf[4096];
    while (pipe && fgets(buf, sizeof buf, pipe))
        out += buf;
    if (pipe) out += "\nexit=" + std::to_string(WEXITSTATUS(pclose(pipe)));
    return out;
}

const fs::path FARM = fs::path(CRACKLE_SOURCE_DIR) / "docs" / "farm";

} // namespace

TEST_SUITE("app") {
    TEST_CASE("batch: seed lists take ranges and lists and refuse anything else in words") {
        CHECK(app::parse_seed_list("1-3,7", "--seeds") == std::vector<std::uint64_t>{1, 2, 3, 7});
        CHECK(app::parse_seed_list(" 5 ", "--seeds") == std::vector<std::uint64_t>{5});
        CHECK(app::parse_seed_list("1-100", "--seeds").size() == 100);
        for (const char* bad : {"", "1..10", "-1", "3-1", "a", "1,,2", "1-", "0-100000", "9000000000000000001"}) {
            CAPTURE(bad);
            CHECK_THROWS_AS(app::parse_seed_list(bad, "--seeds"), InputError);
        }
        // The CLI says it in words: no 300-digit range.
        const auto r = run_cli({"bake", "mud", "--seeds", "1..10"});
        CHECK(r.code == 2);
        CHECK(r.err.find("'1..10' is not a seed or a range of seeds") != std::string::npos);
        CHECK(r.err.size() < 300);
    }

    TEST_CASE("batch: every variant falls in exactly one shard, from --shard, Slurm's and Kubernetes' variables") {
        const Env clear({{"SLURM_ARRAY_TASK_ID", nullptr},
                         {"SLURM_ARRAY_TASK_MIN", nullptr},
                         {"SLURM_ARRAY_TASK_COUNT", nullptr},
                         {"JOB_COMPLETION_INDEX", nullptr},
                         {"CRACKLE_SHARD_COUNT", nullptr}});
        for (int n = 1; n <= 7; ++n) {
            std::vector<int> hits(53, 0);
            for (int i = 1; i <= n; ++i) {
                const app::Shard s = app::resolve_shard(std::to_string(i) + "/" + std::to_string(n));
                for (std::size_t v = 0; v < hits.size(); ++v)
                    hits[v] += s.contains(v) ? 1 : 0;
            }
            CHECK(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
        }
        CHECK(app::resolve_shard("").count == 1);
        {
            const Env slurm(
                {{"SLURM_ARRAY_TASK_ID", "7"}, {"SLURM_ARRAY_TASK_MIN", "5"}, {"SLURM_ARRAY_TASK_COUNT", "4"}});
            const app::Shard s = app::resolve_shard("");
            CHECK(s.index == 3);
            CHECK(s.count == 4);
            CHECK(s.source == "SLURM_ARRAY_TASK_ID");
            CHECK(app::resolve_shard("2/9").index == 2); // an explicit flag wins
        }
        {
            const Env slurm(
                {{"SLURM_ARRAY_TASK_ID", "9"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_COUNT", "3"}});
            CHECK_THROWS_AS(app::resolve_shard(""), InputError); // a gap in the array
        }
        {
            const Env k8s({{"JOB_COMPLETION_INDEX", "0"}});
            CHECK_THROWS_AS(app::resolve_shard(""), InputError); // no count
            CHECK(app::resolve_shard("5").index == 1);
            CHECK(app::resolve_shard("5").count == 5);
            const Env count({{"CRACKLE_SHARD_COUNT", "4"}});
            CHECK(app::resolve_shard("").count == 4);
        }
        for (const char* bad : {"0/3", "4/3", "1/0", "a/b", "3/", "5"})
            CHECK_THROWS_AS(app::resolve_shard(bad), InputError);
    }

    TEST_CASE("batch: output names expand their fields and never leave the output folder") {
        const app::NameFields f{"mud-thin", 42, "v7"};
        const app::OutputNames names("{preset}_{seed}_{map}", f, "--name");
        CHECK(names.base() == "mud-thin_42");
        CHECK(names.map_file("out", {"Color", "png", {}}) == fs::path("out/mud-thin_42_Color.png"));
        CHECK(app::OutputNames("{variant}", f, "x").map_file("o", {"ORM", "png", {}}) == fs::path("o/v7_ORM.png"));
        CHECK(app::OutputNames("{map}/{preset}", f, "x").map_file("o", {"ID", "png", {}})
              == fs::path("o/ID/mud-thin.png"));
        CHECK(app::OutputNames("{map}/{preset}", f, "x").base() == "mud-thin");
        for (const std::string& bad :
             {std::string("../escaped"), std::string("/etc/x"), std::string("a/../../b"), std::string("a\\b"),
              std::string("nul\0byte", 8), std::string("{sede}"), std::string(300, 'n'), std::string("")}) {
            CAPTURE(bad);
            CHECK_THROWS_AS(app::OutputNames(bad, f, "--name"), InputError);
        }
        // Through the CLI: refused before any work, nothing written.
        const fs::path dir = test::scratch_dir("batch-names");
        const auto r = run_cli({"bake", "mud", "--set", "bake.name=\"../escaped\"", "--out", (dir / "o").string()});
        CHECK(r.code == 2);
        CHECK(r.err.find("would leave the output folder") != std::string::npos);
        CHECK(!fs::exists(dir / "o"));
        CHECK(!fs::exists(dir / "escaped_Color.png"));
    }

    TEST_CASE("batch: manifests in JSON Lines and TOML give the same variants, and mistakes name file and line") {
        const fs::path dir = test::scratch_dir("batch-manifest");
        test::write_text(dir / "m.jsonl", "{\"preset\": \"mud\", \"seed\": 3, \"name\": \"a_{seed}\", \"set\": "
                                          "{\"bake.color\": [0.5, 0.4, 0.3], \"bake.size\": 64}}\n\n"
                                          "{\"preset\": \"bark\", \"seeds\": \"1-2\", \"set\": [\"bake.size=64\"]}\n");
        test::write_text(dir / "m.toml", "[[variant]]\npreset = \"mud\"\nseed = 3\nname = \"a_{seed}\"\n"
                                         "set = { \"bake.color\" = [0.5, 0.4, 0.3], \"bake.size\" = 64 }\n\n"
                                         "[[variant]]\npreset = \"bark\"\nseeds = \"1-2\"\nset = [\"bake.size=64\"]\n");
        for (const char* file : {"m.jsonl", "m.toml"}) {
            CAPTURE(file);
            const auto v = app::read_manifest(dir / file);
            REQUIRE(v.size() == 3);
            CHECK(v[0].preset.name_or_path == "mud");
            CHECK(v[0].preset.seed == 3);
            CHECK(v[0].name == "a_{seed}");
            CHECK(v[0].preset.overrides.size() == 2);
            CHECK(v[1].preset.seed == 1);
            CHECK(v[2].preset.seed == 2);
            CHECK(v[2].index == 2);
            const auto r = run_cli({"batch", (dir / file).string(), "--list", "--out", (dir / "o").string()});
            REQUIRE_MESSAGE(r.code == 0, r.err);
            CHECK(r.out == "0\ta_3\tmud\t3\n1\tbark_1\tbark\t1\n2\tbark_2\tbark\t2\n");
        }
        auto refused = [&](const std::string& text, const std::string& where, const std::string& what) {
            test::write_text(dir / "bad.jsonl", text);
            const auto r = run_cli({"batch", (dir / "bad.jsonl").string(), "--list"});
            CHECK(r.code == 2);
            CHECK_MESSAGE(r.err.find(where) != std::string::npos, r.err);
            CHECK_MESSAGE(r.err.find(what) != std::string::npos, r.err);
        };
        refused("{\"preset\": \"mud\"}\n{\"presett\": \"mud\"}\n", "bad.jsonl:2", "unknown key 'presett'");
        refused("{\"seed\": 1}\n", "bad.jsonl:1", "no preset");
        refused("{\"preset\": \"mud\"}\n{\"preset\": \"mud\"\n", "bad.jsonl:2", "");
        refused("{\"preset\": \"mud\", \"seed\": -4}\n", "bad.jsonl:1", "wrong type");
        refused("{\"preset\": \"mud\", \"set\": {\"bake.colr\": 1}}\n", "bad.jsonl:1", "bake.colr");
        refused("{\"preset\": \"mud\", \"seed\": 1}\n{\"preset\": \"mud\", \"seed\": 1}\n", "bad.jsonl:2",
                "writes the same files as");
    }

    TEST_CASE("batch: the Slurm array script and the Kubernetes Indexed Job in docs/farm parse and cover every "
              "variant of the example manifest exactly once") {
        const fs::path manifest = FARM / "manifest-100.jsonl";
        REQUIRE(app::read_manifest(manifest).size() == 100);
        // Slurm: the script is valid bash; its array range gives the shards.
        const std::string script = read_file(FARM / "bake-array.slurm");
        CHECK(shell("bash -n '" + (FARM / "bake-array.slurm").string() + "'").find("exit=0") != std::string::npos);
        std::smatch m;
        REQUIRE(std::regex_search(script, m, std::regex(R"(#SBATCH --array=(\d+)-(\d+))")));
        const int first = std::stoi(m[1].str()), last = std::stoi(m[2].str());
        CHECK(script.find("crackle -q batch \"$MANIFEST\"") != std::string::npos);
        // Kubernetes: the YAML parses, is an Indexed Job, and its shard count is its completions.
        const std::string yaml = shell("/usr/bin/python3 -c \"import json,sys,yaml; print(json.dumps(yaml.safe_load("
                                       "open(sys.argv[1]))))\" '"
                                       + (FARM / "bake-indexed-job.yaml").string() + "'");
        REQUIRE_MESSAGE(yaml.find("exit=0") != std::string::npos, yaml);
        const Json job = Json::parse(yaml.substr(0, yaml.find("\nexit=")), "bake-indexed-job.yaml");
        CHECK(job.find("kind")->as_string() == "Job");
        const Json& spec = *job.find("spec");
        CHECK(spec.find("completionMode")->as_string() == "Indexed");
        const int completions = static_cast<int>(spec.find("completions")->as_number());
        const Json& container = spec.find("template")->find("spec")->find("containers")->elements().at(0);
        std::string count;
        for (const Json& e : container.find("env")->elements())
            if (e.find("name")->as_string() == "CRACKLE_SHARD_COUNT") count = e.find("value")->as_string();
        CHECK(count == std::to_string(completions));

        // Each scheduler's tasks, run as the scheduler would run them: every variant exactly once.
        auto coverage = [&](const std::vector<std::vector<std::pair<const char*, std::string>>>& tasks) {
            std::vector<int> hits(100, 0);
            for (const auto& vars : tasks) {
                std::vector<std::pair<const char*, const char*>> set;
                for (const auto& [k, v] : vars)
                    set.emplace_back(k, v.c_str());
                const Env env({{"SLURM_ARRAY_TASK_ID", nullptr},
                               {"SLURM_ARRAY_TASK_MIN", nullptr},
                               {"SLURM_ARRAY_TASK_COUNT", nullptr},
                               {"JOB_COMPLETION_INDEX", nullptr},
                               {"CRACKLE_SHARD_COUNT", nullptr}});
                for (const auto& [k, v] : set)
                    setenv(k, v, 1);
                const auto r = run_cli({"batch", manifest.string(), "--list"});
                REQUIRE_MESSAGE(r.code == 0, r.err);
                for (std::size_t i : indices_of(r.out))
                    ++hits.at(i);
            }
            return std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; });
        };
        std::vector<std::vector<std::pair<const char*, std::string>>> slurm, k8s;
        for (int id = first; id <= last; ++id)
            slurm.push_back({{"SLURM_ARRAY_TASK_ID", std::to_string(id)},
                             {"SLURM_ARRAY_TASK_MIN", std::to_string(first)},
                             {"SLURM_ARRAY_TASK_COUNT", std::to_string(last - first + 1)}});
        for (int k = 0; k < completions; ++k)
            k8s.push_back({{"JOB_COMPLETION_INDEX", std::to_string(k)}, {"CRACKLE_SHARD_COUNT", count}});
        CHECK(coverage(slurm));
        CHECK(coverage(k8s));
    }

    TEST_CASE("batch: two shards and a merge bake every variant once, and a rerun after kill -9 skips finished "
              "variants and completes the rest") {
        if (!test::gl_context_or_skip()) return;
        const fs::path dir = test::scratch_dir("batch-run");
        std::string lines;
        for (int seed = 1; seed <= 4; ++seed)
            lines += "{\"preset\": \"mud\", \"seed\": " + std::to_string(seed)
                     + ", \"set\": {\"simulation.elements\": 300, \"bake.size\": 32}}\n";
        const fs::path manifest = test::write_text(dir / "m.jsonl", lines);
        const std::string out = (dir / "out").string();
        const Env clear({{"SLURM_ARRAY_TASK_ID", nullptr}, {"JOB_COMPLETION_INDEX", nullptr}});

        // Shard 1 of 2, then a merge that finds shard 2's variants missing.
        auto r = run_cli({"-q", "batch", manifest.string(), "--out", out, "--shard", "1/2"});
        REQUIRE_MESSAGE(r.code == 0, r.err);
        CHECK(fs::exists(dir / "out" / "mud_1_Color.png"));
        CHECK(fs::exists(dir / "out" / "mud_3.json"));
        CHECK(!fs::exists(dir / "out" / "mud_2.json"));
        r = run_cli({"batch", manifest.string(), "--out", out, "--merge"});
        CHECK(r.code == 1);
        CHECK(r.out.find("2 of 4 variants done") != std::string::npos);

        // Shard 2 is killed with SIGKILL while it works; the rerun finishes it.
        const std::string cmd =
            std::string(CRACKLE_BINARY) + " -q batch '" + manifest.string() + "' --out '" + out + "' --shard 2/2";
        const pid_t pid = fork();
        REQUIRE(pid >= 0);
        if (pid == 0) {
            execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), static_cast<char*>(nullptr));
            _exit(127);
        }
        // Kill once the first of its variants has its report (mid-batch), or after 60 s.
        const auto start = std::chrono::steady_clock::now();
        while (!fs::exists(dir / "out" / "mud_2.json")
               && std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        kill(pid, SIGKILL);
        int status = 0;
        waitpid(pid, &status, 0);
        const bool first_done = fs::exists(dir / "out" / "mud_2.json");
        CHECK(first_done);

        r = run_cli({"batch", manifest.string(), "--out", out, "--shard", "2/2"});
        REQUIRE_MESSAGE(r.code == 0, r.err);
        CHECK(r.out.find("mud_2: already done") != std::string::npos);
        CHECK(r.out.find("mud_4: done") != std::string::npos);
        r = run_cli({"batch", manifest.string(), "--out", out, "--merge", "--size", "48"}); // options do not matter
        CHECK_MESSAGE(r.code == 0, r.out);
        const Json merged = Json::parse(read_file(dir / "out" / "batch-summary.json"), "merged");
        CHECK(merged.find("done")->as_number() == 4);
        for (const Json& v : merged.find("variants")->elements())
            CHECK(v.find("shards")->elements().size() == 1); // baked exactly once
        // No temporary file of the killed run is left, and every report's files are complete PNGs.
        for (const auto& e : fs::directory_iterator(dir / "out"))
            CHECK_MESSAGE(e.path().string().find(".tmp") == std::string::npos, e.path().string());
        for (int seed = 1; seed <= 4; ++seed) {
            const Json report = Json::parse(read_file(dir / "out" / ("mud_" + std::to_string(seed) + ".json")), "r");
            CHECK(report.find("files")->elements().size() == 8);
            for (const Json& f : report.find("files")->elements()) {
                const std::string bytes = read_file(f.as_string());
                CHECK(bytes.substr(bytes.size() - 8, 4) == "IEND");
            }
        }
    }

    TEST_CASE("batch: bake --maps packs ORM and a Unity mask map at the asked bit depths, and --mesh writes meshes "
              "beside the maps in the same run, sharing their files") {
        if (!test::gl_context_or_skip()) return;
        const fs::path dir = test::scratch_dir("batch-maps");
        auto r =
            run_cli({"-q", "bake", "mud", "--size", "32", "--set", "simulation.elements=300", "--maps",
                     "Color,NormalGL,Roughness,AmbientOcclusion,ORM,MaskMap", "--bit-depth", "NormalGL=16,Roughness=16",
                     "--mesh", "gltf,obj,glb", "--out", (dir / "o").string(), "--name", "{preset}_{seed}_{map}"});
        REQUIRE_MESSAGE(r.code == 0, r.err);
        // PNG header: bit depth at byte 24, colour type at 25 (0 grey, 2 RGB, 6 RGBA).
        auto header = [&](const char* file) {
            const std::string b = read_file(dir / "o" / file);
            return std::make_pair(int(static_cast<unsigned char>(b[24])), int(static_cast<unsigned char>(b[25])));
        };
        CHECK(header("mud_1_Color.png") == std::make_pair(8, 2));
        CHECK(header("mud_1_NormalGL.png") == std::make_pair(16, 2));
        CHECK(header("mud_1_Roughness.png") == std::make_pair(16, 0));
        CHECK(header("mud_1_AmbientOcclusion.png") == std::make_pair(8, 0));
        CHECK(header("mud_1_ORM.png") == std::make_pair(8, 2));
        CHECK(header("mud_1_MaskMap.png") == std::make_pair(8, 6));
        CHECK(!fs::exists(dir / "o" / "mud_1_ID.png"));
        // ORM's red is the occlusion map.
        int w = 0, h = 0, w2 = 0, h2 = 0;
        const std::string orm = read_file(dir / "o" / "mud_1_ORM.png"),
                          ao = read_file(dir / "o" / "mud_1_AmbientOcclusion.png");
        const auto orm_rgb = io::decode_png_rgb8(std::vector<std::uint8_t>(orm.begin(), orm.end()), w, h);
        const auto ao_rgb = io::decode_png_rgb8(std::vector<std::uint8_t>(ao.begin(), ao.end()), w2, h2);
        REQUIRE(orm_rgb.size() == ao_rgb.size());
        for (std::size_t i = 0; i < orm_rgb.size(); i += 3)
            CHECK(orm_rgb[i] == ao_rgb[i]);
        // The meshes are named after the base name, and their maps are the bake's own files.
        for (const char* f : {"mud_1.gltf", "mud_1.bin", "mud_1.obj", "mud_1.mtl", "mud_1.glb"})
            CHECK_MESSAGE(fs::exists(dir / "o" / f), f);
        std::size_t files = 0;
        for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir / "o"))
            ++files;
        CHECK(files == 11); // 6 maps + 5 mesh files: NormalGL, Color, ORM, Roughness shared, not copied
        // Refused in words before any work.
        r = run_cli({"bake", "mud", "--maps", "Color,Colour", "--out", (dir / "x").string()});
        CHECK(r.code == 2);
        CHECK(r.err.find("did you mean 'Color'") != std::string::npos);
        r = run_cli({"bake", "mud", "--bit-depth", "ID=16", "--out", (dir / "x").string()});
        CHECK(r.code == 2);
        CHECK(!fs::exists(dir / "x"));
    }
}
