// slang_check: compile one HLSL entry point with Slang's HLSL front end.
//
// An "independent compiler" check for the HLSL that volfog exports: the file
// is parsed and type-checked by Slang as HLSL (SLANG_SOURCE_LANGUAGE_HLSL),
// then lowered and code-generated for a target that needs no external tool
// (no DXC, no glslang).  See tools/README.md for the full description.
//
// Usage:
//   slang_check --stage compute|vertex|fragment --entry NAME
//               [--profile PROFILE] [--target hlsl|spirv] [--werror]
//               [-I DIR]... [-D NAME[=VALUE]]... [-o OUT] FILE.hlsl
//
// Exit status: 0 success, 1 compile failure (or a warning with --werror),
//              2 bad command line / unreadable file / Slang start-up failure.
//
// Slang's diagnostics ("FILE(LINE): error NNNNN: ...") go to stderr verbatim.
// A final line "slang_check: FILE: ok|FAILED ..." always names the file.

#include <slang.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

// The per-translation-unit source language can only be chosen through the
// compile-request API, which Slang marks [[deprecated]] in favour of the
// module/session API (that one always treats source as Slang).  We need the
// HLSL front end, so we use it knowingly and silence the deprecation warning.
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif

namespace {

const char* kTool = "slang_check";

// Profile used for `--target spirv` when `--profile` is not given.  SPIR-V 1.3
// is what Vulkan 1.1 guarantees and what lavapipe / every desktop driver
// accepts, so the module can be dispatched later.
const char* kDefaultSpirvProfile = "spirv_1_3";
const char* kDefaultHlslProfile = "sm_6_0";

// Minimal owning pointer for Slang COM-style objects (the wheel does not ship
// slang-com-ptr.h): releases the reference it holds when it goes away.
template<typename T>
class Ref
{
public:
    Ref() = default;
    Ref(const Ref&) = delete;
    Ref& operator=(const Ref&) = delete;
    ~Ref()
    {
        if (ptr_)
            ptr_->release();
    }
    T** writeRef() { return &ptr_; } // for out-parameters of Slang calls
    T* operator->() const { return ptr_; }
    explicit operator bool() const { return ptr_ != nullptr; }

private:
    T* ptr_ = nullptr;
};

enum class Target
{
    Default, // in-memory: HLSL at --profile, then SPIR-V at spirv_1_3
    Hlsl,    // HLSL source text at --profile (sm_6_0 by default)
    Spirv,   // SPIR-V binary at --profile (spirv_1_3 by default)
};

struct Options
{
    std::string stage;
    std::string entry;
    std::string profile; // empty: target's default
    Target target = Target::Default;
    bool werror = false;
    std::vector<std::string> includeDirs;
    std::vector<std::pair<std::string, std::string>> defines;
    std::string output;
    std::string file;
};

void usage(FILE* out)
{
    std::fprintf(
        out,
        "usage: %s --stage compute|vertex|fragment --entry NAME\n"
        "         [--profile PROFILE] [--target hlsl|spirv] [--werror]\n"
        "         [-I DIR]... [-D NAME[=VALUE]]... [-o OUT] FILE.hlsl\n"
        "\n"
        "Compiles FILE as HLSL with Slang (entry point NAME for the stage).\n"
        "  (no --target)    check only: generate HLSL (profile, default sm_6_0)\n"
        "                   and SPIR-V (spirv_1_3) in memory\n"
        "  --target hlsl    generate HLSL text (profile default sm_6_0)\n"
        "  --target spirv   generate SPIR-V for Vulkan (profile default spirv_1_3)\n"
        "  -o OUT           write the generated code (needs --target)\n"
        "  --werror         treat warnings as errors\n"
        "Exit: 0 ok, 1 compile error, 2 usage/IO error.\n",
        kTool);
}

// Prints "slang_check: <msg>" and returns the usage-error exit code.
int usageError(const std::string& msg)
{
    std::fprintf(stderr, "%s: %s\n", kTool, msg.c_str());
    usage(stderr);
    return 2;
}

// Parses argv into `opts`.  Returns 0 on success, else the exit code to use
// (-1 means "--help was printed, exit 0").
int parseArgs(int argc, char** argv, Options& opts)
{
    for (int i = 1; i < argc; ++i)
    {
        std::string arg = argv[i];
        // Options that take a value accept "--opt VALUE"; -I/-D/-o also
        // accept the glued form "-IDIR", "-DNAME=V", "-oOUT".
        auto value = [&](std::string& dst) -> bool
        {
            if (i + 1 >= argc)
                return false;
            dst = argv[++i];
            return true;
        };
        std::string v;
        if (arg == "-h" || arg == "--help")
        {
            usage(stdout);
            return -1;
        }
        else if (arg == "--stage")
        {
            if (!value(opts.stage))
                return usageError("--stage needs a value");
        }
        else if (arg == "--entry")
        {
            if (!value(opts.entry))
                return usageError("--entry needs a value");
        }
        else if (arg == "--profile")
        {
            if (!value(opts.profile))
                return usageError("--profile needs a value");
        }
        else if (arg == "--target")
        {
            if (!value(v))
                return usageError("--target needs a value");
            if (v == "hlsl")
                opts.target = Target::Hlsl;
            else if (v == "spirv")
                opts.target = Target::Spirv;
            else
                return usageError(
                    "unsupported --target '" + v +
                    "' (supported: hlsl, spirv; dxil needs DXC, which is not used)");
        }
        else if (arg == "--werror")
        {
            opts.werror = true;
        }
        else if (arg.rfind("-I", 0) == 0)
        {
            if (arg.size() > 2)
                opts.includeDirs.push_back(arg.substr(2));
            else if (value(v))
                opts.includeDirs.push_back(v);
            else
                return usageError("-I needs a directory");
        }
        else if (arg.rfind("-D", 0) == 0)
        {
            if (arg.size() > 2)
                v = arg.substr(2);
            else if (!value(v))
                return usageError("-D needs NAME[=VALUE]");
            size_t eq = v.find('=');
            if (eq == 0 || v.empty())
                return usageError("bad -D '" + v + "'");
            if (eq == std::string::npos)
                opts.defines.emplace_back(v, "1");
            else
                opts.defines.emplace_back(v.substr(0, eq), v.substr(eq + 1));
        }
        else if (arg.rfind("-o", 0) == 0)
        {
            if (arg.size() > 2)
                opts.output = arg.substr(2);
            else if (!value(opts.output))
                return usageError("-o needs a file name");
        }
        else if (!arg.empty() && arg[0] == '-')
        {
            return usageError("unknown option '" + arg + "'");
        }
        else
        {
            if (!opts.file.empty())
                return usageError("more than one input file ('" + opts.file + "', '" + arg + "')");
            opts.file = arg;
        }
    }
    if (opts.file.empty())
        return usageError("no input file");
    if (opts.stage.empty() || opts.entry.empty())
        return usageError("--stage and --entry are required");
    if (!opts.output.empty() && opts.target == Target::Default)
        return usageError("-o needs --target hlsl or --target spirv");
    return 0;
}

bool stageFromName(const std::string& name, SlangStage& out)
{
    if (name == "compute")
        out = SLANG_STAGE_COMPUTE;
    else if (name == "vertex")
        out = SLANG_STAGE_VERTEX;
    else if (name == "fragment")
        out = SLANG_STAGE_FRAGMENT;
    else
        return false;
    return true;
}

// One code-generation target of the compile request.
struct TargetSpec
{
    SlangCompileTarget format;
    std::string profile;
    int index = -1; // index returned by addCodeGenTarget
};

int run(const Options& opts)
{
    const char* file = opts.file.c_str();

    SlangStage stage;
    if (!stageFromName(opts.stage, stage))
        return usageError("unknown --stage '" + opts.stage + "' (compute, vertex, fragment)");

    // Fail early with a clear message rather than Slang's generic one.
    if (!std::ifstream(opts.file).good())
    {
        std::fprintf(stderr, "%s: %s: cannot read file\n", kTool, file);
        return 2;
    }

    // Which targets to generate code for.
    std::vector<TargetSpec> targets;
    switch (opts.target)
    {
    case Target::Default:
        targets.push_back({SLANG_HLSL, opts.profile.empty() ? kDefaultHlslProfile : opts.profile});
        targets.push_back({SLANG_SPIRV, kDefaultSpirvProfile});
        break;
    case Target::Hlsl:
        targets.push_back({SLANG_HLSL, opts.profile.empty() ? kDefaultHlslProfile : opts.profile});
        break;
    case Target::Spirv:
        targets.push_back({SLANG_SPIRV, opts.profile.empty() ? kDefaultSpirvProfile : opts.profile});
        break;
    }

    Ref<slang::IGlobalSession> global;
    if (SLANG_FAILED(slang::createGlobalSession(global.writeRef())))
    {
        std::fprintf(stderr, "%s: %s: could not create a Slang global session\n", kTool, file);
        return 2;
    }

    Ref<slang::ICompileRequest> request;
    if (SLANG_FAILED(global->createCompileRequest(request.writeRef())))
    {
        std::fprintf(stderr, "%s: %s: could not create a Slang compile request\n", kTool, file);
        return 2;
    }

    for (TargetSpec& t : targets)
    {
        SlangProfileID profile = global->findProfile(t.profile.c_str());
        if (profile == SLANG_PROFILE_UNKNOWN)
            return usageError("unknown profile '" + t.profile + "'");
        t.index = request->addCodeGenTarget(t.format);
        request->setTargetProfile(t.index, profile);
        if (t.format == SLANG_SPIRV)
            request->setTargetFlags(t.index, SLANG_TARGET_FLAG_GENERATE_SPIRV_DIRECTLY);
    }

    for (const std::string& dir : opts.includeDirs)
        request->addSearchPath(dir.c_str());
    for (const auto& d : opts.defines)
        request->addPreprocessorDefine(d.first.c_str(), d.second.c_str());
    if (opts.werror)
        request->setDiagnosticFlags(SLANG_DIAGNOSTIC_FLAG_TREAT_WARNINGS_AS_ERRORS);

    // Options that only exist in slangc's command-line form.
    std::vector<const char*> extraArgs = {
        // Keep the HLSL entry-point name in SPIR-V (Slang renames it "main"
        // otherwise), so the module can be dispatched by its real name.
        "-fvk-use-entrypoint-name",
    };
    if (opts.target == Target::Default)
    {
        // The SPIR-V of the default check is never used, so its Vulkan-only
        // warning 39029 ("D3D register without Vulkan binding or shift",
        // issued for every `register(...)` without [[vk::binding]]) is noise.
        extraArgs.push_back("-warnings-disable");
        extraArgs.push_back("39029");
    }
    if (SLANG_FAILED(request->processCommandLineArguments(
            extraArgs.data(), static_cast<int>(extraArgs.size()))))
    {
        std::fprintf(stderr, "%s: %s: Slang rejected its internal options\n", kTool, file);
        return 2;
    }

    // The input is HLSL, not Slang: use the HLSL front end explicitly.
    int unit = request->addTranslationUnit(SLANG_SOURCE_LANGUAGE_HLSL, nullptr);
    request->addTranslationUnitSourceFile(unit, file);
    int entryIndex = request->addEntryPoint(unit, opts.entry.c_str(), stage);

    SlangResult result = request->compile();

    // Slang's own diagnostics, verbatim (they carry FILE(LINE) positions).
    const char* diagnostics = request->getDiagnosticOutput();
    if (diagnostics && *diagnostics)
    {
        std::fputs(diagnostics, stderr);
        size_t n = std::strlen(diagnostics);
        if (diagnostics[n - 1] != '\n')
            std::fputc('\n', stderr);
    }

    if (SLANG_FAILED(result))
    {
        std::fprintf(
            stderr,
            "%s: %s: FAILED (entry '%s', stage %s)\n",
            kTool,
            file,
            opts.entry.c_str(),
            opts.stage.c_str());
        return 1;
    }

    // Make sure every target really produced code for the entry point.
    for (const TargetSpec& t : targets)
    {
        Ref<ISlangBlob> code;
        if (SLANG_FAILED(request->getEntryPointCodeBlob(entryIndex, t.index, code.writeRef())) ||
            !code || code->getBufferSize() == 0)
        {
            std::fprintf(
                stderr,
                "%s: %s: FAILED (no %s code generated for entry '%s')\n",
                kTool,
                file,
                t.profile.c_str(),
                opts.entry.c_str());
            return 1;
        }
        if (!opts.output.empty())
        {
            std::ofstream out(opts.output, std::ios::binary);
            out.write(static_cast<const char*>(code->getBufferPointer()), code->getBufferSize());
            if (!out.good())
            {
                std::fprintf(stderr, "%s: %s: cannot write '%s'\n", kTool, file, opts.output.c_str());
                return 2;
            }
        }
    }

    std::string profiles;
    for (const TargetSpec& t : targets)
        profiles += (profiles.empty() ? "" : ", ") + t.profile;
    std::fprintf(
        stderr,
        "%s: %s: ok (entry '%s', stage %s, %s)\n",
        kTool,
        file,
        opts.entry.c_str(),
        opts.stage.c_str(),
        profiles.c_str());
    return 0;
}

} // namespace

int main(int argc, char** argv)
{
    Options opts;
    int rc = parseArgs(argc, argv, opts);
    if (rc == -1)
        return 0;
    if (rc != 0)
        return rc;
    return run(opts);
}
