/*
 * gl_link: compile and link GLSL shaders as ONE program in the system's
 * OpenGL 4.5 core driver (Mesa llvmpipe here), headless through EGL's
 * surfaceless platform: no window, no X, no surface.
 *
 * usage: gl_link [--json] STAGE:FILE [STAGE:FILE...]
 *        STAGE is vert, frag or comp.
 *
 * Every file is compiled as a shader of its stage; all shaders are attached
 * to one program, which is linked.  Info logs (errors and warnings) go to
 * stderr, prefixed with the file name.  With --json, a successful link prints
 * the program's active resources to stdout as one JSON object:
 *
 *   {"uniform_blocks":        [{"name": N, "binding": B, "data_size": S}],
 *    "shader_storage_blocks": [{"name": N, "binding": B, "data_size": S}],
 *    "opaque_uniforms":       [{"name": N, "type": T, "binding": B}]}
 *
 * where opaque_uniforms are the active sampler and image uniforms, "type" is
 * their GLSL type name and "binding" the value read with glGetUniformiv
 * (the texture unit / image unit set by layout(binding = ...)).
 *
 * Exit status: 0 linked, 1 a compile or link error, 2 usage, file or
 * EGL/GL start-up error.
 */

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *tool = "gl_link";

/* One STAGE:FILE argument. */
struct shader_arg {
    GLenum type;      /* GL_VERTEX_SHADER, ... */
    const char *path; /* points into argv */
};

static void usage(FILE *out)
{
    fprintf(out,
            "usage: %s [--json] STAGE:FILE [STAGE:FILE...]\n"
            "  STAGE: vert, frag or comp. All files are linked into ONE program\n"
            "  in an OpenGL 4.5 core context (EGL surfaceless).\n"
            "  --json  on success, print the program's uniform blocks, shader\n"
            "          storage blocks and sampler/image uniforms as JSON.\n"
            "Exit: 0 linked, 1 compile/link error, 2 usage/IO/EGL error.\n",
            tool);
}

static int stage_from_name(const char *name, size_t len, GLenum *out)
{
    if (len == 4 && strncmp(name, "vert", 4) == 0)
        *out = GL_VERTEX_SHADER;
    else if (len == 4 && strncmp(name, "frag", 4) == 0)
        *out = GL_FRAGMENT_SHADER;
    else if (len == 4 && strncmp(name, "comp", 4) == 0)
        *out = GL_COMPUTE_SHADER;
    else
        return 0;
    return 1;
}

/* Reads a whole file into a NUL-terminated malloc'd buffer, or NULL. */
static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = NULL;
    long size = -1;
    if (fseek(f, 0, SEEK_END) == 0 && (size = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (buf = malloc((size_t)size + 1)) != NULL && fread(buf, 1, (size_t)size, f) == (size_t)size) {
        buf[size] = '\0';
    } else {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    return buf;
}

/* Prints an info log to stderr, each line prefixed with "PREFIX: ". */
static void print_log(const char *prefix, const char *log)
{
    while (*log) {
        const char *end = strchr(log, '\n');
        size_t len = end ? (size_t)(end - log) : strlen(log);
        if (len > 0)
            fprintf(stderr, "%s: %.*s\n", prefix, (int)len, log);
        log += len + (end ? 1 : 0);
    }
}

/* ---------------------------------------------------------------- EGL --- */

static int has_extension(const char *list, const char *name)
{
    size_t len = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += len)
        if ((p == list || p[-1] == ' ') && (p[len] == ' ' || p[len] == '\0'))
            return 1;
    return 0;
}

/*
 * Creates an OpenGL 4.5 core context on Mesa's surfaceless EGL platform and
 * makes it current without any surface.  Returns 0 on success; on failure
 * prints why and returns 2.
 */
static int make_context(void)
{
    const char *client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client_ext, "EGL_MESA_platform_surfaceless")) {
        fprintf(stderr, "%s: EGL has no EGL_MESA_platform_surfaceless (is libegl-mesa0 installed?)\n", tool);
        return 2;
    }
    EGLDisplay dpy = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    EGLint major, minor;
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, &major, &minor)) {
        fprintf(stderr, "%s: eglInitialize on the surfaceless platform failed (0x%x)\n", tool, eglGetError());
        return 2;
    }
    const char *ext = eglQueryString(dpy, EGL_EXTENSIONS);
    if (!has_extension(ext, "EGL_KHR_surfaceless_context")) {
        fprintf(stderr, "%s: EGL display lacks EGL_KHR_surfaceless_context\n", tool);
        return 2;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        fprintf(stderr, "%s: eglBindAPI(EGL_OPENGL_API) failed (0x%x)\n", tool, eglGetError());
        return 2;
    }

    /* No surface will be made, so any config that can do desktop GL will do;
     * with EGL_KHR_no_config_context none is needed at all. */
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!has_extension(ext, "EGL_KHR_no_config_context")) {
        const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLint count = 0;
        if (!eglChooseConfig(dpy, config_attribs, &config, 1, &count) || count < 1) {
            fprintf(stderr, "%s: no EGL config supports OpenGL (0x%x)\n", tool, eglGetError());
            return 2;
        }
    }

    const EGLint context_attribs[] = {
        EGL_CONTEXT_MAJOR_VERSION, 4,
        EGL_CONTEXT_MINOR_VERSION, 5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_NONE,
    };
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, context_attribs);
    if (ctx == EGL_NO_CONTEXT) {
        fprintf(stderr, "%s: cannot create an OpenGL 4.5 core context (0x%x)\n", tool, eglGetError());
        return 2;
    }
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        fprintf(stderr, "%s: eglMakeCurrent without a surface failed (0x%x)\n", tool, eglGetError());
        return 2;
    }
    return 0;
}

/* ------------------------------------------------------- introspection --- */

/* GLSL names of the sampler and image uniform types. */
static const struct {
    GLenum type;
    const char *name;
} opaque_types[] = {
    {GL_SAMPLER_1D, "sampler1D"},
    {GL_SAMPLER_2D, "sampler2D"},
    {GL_SAMPLER_3D, "sampler3D"},
    {GL_SAMPLER_CUBE, "samplerCube"},
    {GL_SAMPLER_1D_SHADOW, "sampler1DShadow"},
    {GL_SAMPLER_2D_SHADOW, "sampler2DShadow"},
    {GL_SAMPLER_1D_ARRAY, "sampler1DArray"},
    {GL_SAMPLER_2D_ARRAY, "sampler2DArray"},
    {GL_SAMPLER_1D_ARRAY_SHADOW, "sampler1DArrayShadow"},
    {GL_SAMPLER_2D_ARRAY_SHADOW, "sampler2DArrayShadow"},
    {GL_SAMPLER_2D_MULTISAMPLE, "sampler2DMS"},
    {GL_SAMPLER_2D_MULTISAMPLE_ARRAY, "sampler2DMSArray"},
    {GL_SAMPLER_CUBE_SHADOW, "samplerCubeShadow"},
    {GL_SAMPLER_BUFFER, "samplerBuffer"},
    {GL_SAMPLER_2D_RECT, "sampler2DRect"},
    {GL_SAMPLER_2D_RECT_SHADOW, "sampler2DRectShadow"},
    {GL_SAMPLER_CUBE_MAP_ARRAY, "samplerCubeArray"},
    {GL_SAMPLER_CUBE_MAP_ARRAY_SHADOW, "samplerCubeArrayShadow"},
    {GL_INT_SAMPLER_1D, "isampler1D"},
    {GL_INT_SAMPLER_2D, "isampler2D"},
    {GL_INT_SAMPLER_3D, "isampler3D"},
    {GL_INT_SAMPLER_CUBE, "isamplerCube"},
    {GL_INT_SAMPLER_1D_ARRAY, "isampler1DArray"},
    {GL_INT_SAMPLER_2D_ARRAY, "isampler2DArray"},
    {GL_INT_SAMPLER_2D_MULTISAMPLE, "isampler2DMS"},
    {GL_INT_SAMPLER_2D_MULTISAMPLE_ARRAY, "isampler2DMSArray"},
    {GL_INT_SAMPLER_BUFFER, "isamplerBuffer"},
    {GL_INT_SAMPLER_2D_RECT, "isampler2DRect"},
    {GL_INT_SAMPLER_CUBE_MAP_ARRAY, "isamplerCubeArray"},
    {GL_UNSIGNED_INT_SAMPLER_1D, "usampler1D"},
    {GL_UNSIGNED_INT_SAMPLER_2D, "usampler2D"},
    {GL_UNSIGNED_INT_SAMPLER_3D, "usampler3D"},
    {GL_UNSIGNED_INT_SAMPLER_CUBE, "usamplerCube"},
    {GL_UNSIGNED_INT_SAMPLER_1D_ARRAY, "usampler1DArray"},
    {GL_UNSIGNED_INT_SAMPLER_2D_ARRAY, "usampler2DArray"},
    {GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE, "usampler2DMS"},
    {GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE_ARRAY, "usampler2DMSArray"},
    {GL_UNSIGNED_INT_SAMPLER_BUFFER, "usamplerBuffer"},
    {GL_UNSIGNED_INT_SAMPLER_2D_RECT, "usampler2DRect"},
    {GL_UNSIGNED_INT_SAMPLER_CUBE_MAP_ARRAY, "usamplerCubeArray"},
    {GL_IMAGE_1D, "image1D"},
    {GL_IMAGE_2D, "image2D"},
    {GL_IMAGE_3D, "image3D"},
    {GL_IMAGE_2D_RECT, "image2DRect"},
    {GL_IMAGE_CUBE, "imageCube"},
    {GL_IMAGE_BUFFER, "imageBuffer"},
    {GL_IMAGE_1D_ARRAY, "image1DArray"},
    {GL_IMAGE_2D_ARRAY, "image2DArray"},
    {GL_IMAGE_CUBE_MAP_ARRAY, "imageCubeArray"},
    {GL_IMAGE_2D_MULTISAMPLE, "image2DMS"},
    {GL_IMAGE_2D_MULTISAMPLE_ARRAY, "image2DMSArray"},
    {GL_INT_IMAGE_1D, "iimage1D"},
    {GL_INT_IMAGE_2D, "iimage2D"},
    {GL_INT_IMAGE_3D, "iimage3D"},
    {GL_INT_IMAGE_2D_RECT, "iimage2DRect"},
    {GL_INT_IMAGE_CUBE, "iimageCube"},
    {GL_INT_IMAGE_BUFFER, "iimageBuffer"},
    {GL_INT_IMAGE_1D_ARRAY, "iimage1DArray"},
    {GL_INT_IMAGE_2D_ARRAY, "iimage2DArray"},
    {GL_INT_IMAGE_CUBE_MAP_ARRAY, "iimageCubeArray"},
    {GL_INT_IMAGE_2D_MULTISAMPLE, "iimage2DMS"},
    {GL_INT_IMAGE_2D_MULTISAMPLE_ARRAY, "iimage2DMSArray"},
    {GL_UNSIGNED_INT_IMAGE_1D, "uimage1D"},
    {GL_UNSIGNED_INT_IMAGE_2D, "uimage2D"},
    {GL_UNSIGNED_INT_IMAGE_3D, "uimage3D"},
    {GL_UNSIGNED_INT_IMAGE_2D_RECT, "uimage2DRect"},
    {GL_UNSIGNED_INT_IMAGE_CUBE, "uimageCube"},
    {GL_UNSIGNED_INT_IMAGE_BUFFER, "uimageBuffer"},
    {GL_UNSIGNED_INT_IMAGE_1D_ARRAY, "uimage1DArray"},
    {GL_UNSIGNED_INT_IMAGE_2D_ARRAY, "uimage2DArray"},
    {GL_UNSIGNED_INT_IMAGE_CUBE_MAP_ARRAY, "uimageCubeArray"},
    {GL_UNSIGNED_INT_IMAGE_2D_MULTISAMPLE, "uimage2DMS"},
    {GL_UNSIGNED_INT_IMAGE_2D_MULTISAMPLE_ARRAY, "uimage2DMSArray"},
};

/* GLSL type name of a sampler/image type, or NULL for any other type. */
static const char *opaque_type_name(GLenum type)
{
    for (size_t i = 0; i < sizeof opaque_types / sizeof opaque_types[0]; ++i)
        if (opaque_types[i].type == type)
            return opaque_types[i].name;
    return NULL;
}

/* Prints a JSON string literal (resource names are identifiers, possibly with
 * '.', '[' and ']', but escape defensively). */
static void print_json_string(const char *s)
{
    putchar('"');
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            printf("\\%c", c);
        else if (c < 0x20)
            printf("\\u%04x", c);
        else
            putchar(c);
    }
    putchar('"');
}

/* Prints the blocks of one interface (uniform or shader storage) as a JSON
 * array of {"name", "binding", "data_size"}. */
static void print_blocks(GLuint program, GLenum interface)
{
    GLint count = 0;
    glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &count);
    putchar('[');
    for (GLint i = 0; i < count; ++i) {
        char name[512];
        glGetProgramResourceName(program, interface, (GLuint)i, sizeof name, NULL, name);
        const GLenum props[] = {GL_BUFFER_BINDING, GL_BUFFER_DATA_SIZE};
        GLint values[2] = {0, 0};
        glGetProgramResourceiv(program, interface, (GLuint)i, 2, props, 2, NULL, values);
        printf("%s{\"name\": ", i ? ", " : "");
        print_json_string(name);
        printf(", \"binding\": %d, \"data_size\": %d}", values[0], values[1]);
    }
    putchar(']');
}

/* Prints the active sampler and image uniforms as a JSON array of
 * {"name", "type", "binding"}. */
static void print_opaque_uniforms(GLuint program)
{
    GLint count = 0;
    int printed = 0;
    glGetProgramInterfaceiv(program, GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
    putchar('[');
    for (GLint i = 0; i < count; ++i) {
        const GLenum props[] = {GL_TYPE, GL_LOCATION};
        GLint values[2] = {0, -1};
        glGetProgramResourceiv(program, GL_UNIFORM, (GLuint)i, 2, props, 2, NULL, values);
        const char *type = opaque_type_name((GLenum)values[0]);
        if (!type)
            continue;
        char name[512];
        glGetProgramResourceName(program, GL_UNIFORM, (GLuint)i, sizeof name, NULL, name);
        GLint binding = -1;
        if (values[1] >= 0)
            glGetUniformiv(program, values[1], &binding);
        printf("%s{\"name\": ", printed++ ? ", " : "");
        print_json_string(name);
        printf(", \"type\": \"%s\", \"binding\": %d}", type, binding);
    }
    putchar(']');
}

/* --------------------------------------------------------------- main --- */

int main(int argc, char **argv)
{
    int json = 0;
    struct shader_arg *shaders = calloc((size_t)argc, sizeof *shaders);
    int nshaders = 0;

    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        const char *colon = strchr(arg, ':');
        if (strcmp(arg, "--json") == 0) {
            json = 1;
        } else if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            usage(stdout);
            return 0;
        } else if (colon && stage_from_name(arg, (size_t)(colon - arg), &shaders[nshaders].type) &&
                   colon[1] != '\0') {
            shaders[nshaders++].path = colon + 1;
        } else {
            fprintf(stderr, "%s: bad argument '%s' (expected --json or STAGE:FILE, STAGE = vert|frag|comp)\n",
                    tool, arg);
            usage(stderr);
            return 2;
        }
    }
    if (nshaders == 0) {
        usage(stderr);
        return 2;
    }

    /* Read every file before touching the driver. */
    char **sources = calloc((size_t)nshaders, sizeof *sources);
    for (int i = 0; i < nshaders; ++i) {
        sources[i] = read_file(shaders[i].path);
        if (!sources[i]) {
            fprintf(stderr, "%s: %s: cannot read file\n", tool, shaders[i].path);
            return 2;
        }
    }

    int rc = make_context();
    if (rc != 0)
        return rc;

    /* Compile each shader; report every failing file, not just the first. */
    GLuint program = glCreateProgram();
    int failed = 0;
    for (int i = 0; i < nshaders; ++i) {
        GLuint shader = glCreateShader(shaders[i].type);
        const GLchar *src = sources[i];
        glShaderSource(shader, 1, &src, NULL);
        glCompileShader(shader);

        GLint ok = GL_FALSE, log_len = 0;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &log_len);
        if (log_len > 1) {
            /* Mesa's lines look like "0:12(3): error: ..."; prefix the file. */
            char *log = malloc((size_t)log_len);
            glGetShaderInfoLog(shader, log_len, NULL, log);
            print_log(shaders[i].path, log);
            free(log);
        }
        if (!ok) {
            fprintf(stderr, "%s: %s: compile failed\n", tool, shaders[i].path);
            failed = 1;
        }
        glAttachShader(program, shader);
        glDeleteShader(shader); /* freed with the program */
    }
    if (failed)
        return 1;

    glLinkProgram(program);
    GLint linked = GL_FALSE, log_len = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &log_len);

    /* The link log is about the program as a whole: name every file. */
    size_t files_len = 1;
    for (int i = 0; i < nshaders; ++i)
        files_len += strlen(shaders[i].path) + 2;
    char *files = calloc(files_len, 1);
    for (int i = 0; i < nshaders; ++i) {
        if (i)
            strcat(files, ", ");
        strcat(files, shaders[i].path);
    }
    if (log_len > 1) {
        char *log = malloc((size_t)log_len);
        glGetProgramInfoLog(program, log_len, NULL, log);
        char *prefix = malloc(files_len + 16);
        snprintf(prefix, files_len + 16, "link (%s)", files);
        print_log(prefix, log);
        free(prefix);
        free(log);
    }
    if (!linked) {
        fprintf(stderr, "%s: link failed (%s)\n", tool, files);
        return 1;
    }

    if (json) {
        printf("{\"uniform_blocks\": ");
        print_blocks(program, GL_UNIFORM_BLOCK);
        printf(", \"shader_storage_blocks\": ");
        print_blocks(program, GL_SHADER_STORAGE_BLOCK);
        printf(", \"opaque_uniforms\": ");
        print_opaque_uniforms(program);
        printf("}\n");
    }
    fprintf(stderr, "%s: ok (%s)\n", tool, files);
    return 0;
}
