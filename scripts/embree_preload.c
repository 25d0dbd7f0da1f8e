/* Preloaded into Embree's peers by bench-peers.sh, to change how Embree runs without
 * a command-line option (neither embreex nor embree_native.c takes a configuration
 * string or scene flags from the command line):
 *
 *   EMBREE_ISA=avx2   appends "isa=avx2" to the configuration string of every
 *                     rtcNewDevice call, so that Embree runs the kernels of that
 *                     instruction set whatever the CPU offers;
 *   EMBREE_ROBUST=1   adds RTC_SCENE_FLAG_ROBUST to every rtcSetSceneFlags call
 *                     (embree_native.c sets NONE), which also switches Embree's
 *                     triangles to a watertight test, as nffrt's.
 *
 *   gcc -O2 -shared -fPIC -o embree_preload.so embree_preload.c -ldl
 *   EMBREE_ISA=avx2 LD_PRELOAD=./embree_preload.so python3 embree_anchor.py ...
 *
 * The real functions are found among the loaded objects (embreex loads its Embree
 * privately, out of RTLD_NEXT's reach).
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <link.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* RTC_SCENE_FLAG_ROBUST of embree3/rtcore_scene.h (Embree 3 and 4). */
#define SCENE_FLAG_ROBUST (1 << 2)

typedef void *(*new_device_fn)(const char *);
typedef void (*set_scene_flags_fn)(void *, int);

struct lookup {
    const char *symbol;
    void *found;
};

static int find_in_embree(struct dl_phdr_info *info, size_t size, void *data)
{
    (void)size;
    struct lookup *l = data;
    if (!info->dlpi_name || !strstr(info->dlpi_name, "libembree"))
        return 0;
    void *lib = dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD);
    if (lib)
        l->found = dlsym(lib, l->symbol);
    return l->found != NULL;
}

/* Embree's own `symbol`; aborts when no Embree is loaded. */
static void *embree(const char *symbol)
{
    struct lookup l = {symbol, NULL};
    dl_iterate_phdr(find_in_embree, &l);
    if (!l.found) {
        fprintf(stderr, "embree_preload: no libembree with %s loaded\n", symbol);
        abort();
    }
    return l.found;
}

void *rtcNewDevice(const char *config)
{
    static new_device_fn real;
    if (!real)
        real = (new_device_fn)embree("rtcNewDevice");
    const char *isa = getenv("EMBREE_ISA");
    if (!isa || !*isa)
        return real(config);
    char buffer[512];
    snprintf(buffer, sizeof buffer, "%s%sisa=%s", config ? config : "", config && *config ? "," : "", isa);
    return real(buffer);
}

void rtcSetSceneFlags(void *scene, int flags)
{
    static set_scene_flags_fn real;
    if (!real)
        real = (set_scene_flags_fn)embree("rtcSetSceneFlags");
    const char *robust = getenv("EMBREE_ROBUST");
    real(scene, robust && !strcmp(robust, "1") ? flags | SCENE_FLAG_ROBUST : flags);
}
