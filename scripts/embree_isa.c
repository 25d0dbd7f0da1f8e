/* Preloaded into Embree's peers by bench-peers.sh (EMBREE_ISA=avx2): appends
 * "isa=$EMBREE_ISA" to the configuration string of every rtcNewDevice call, so that
 * Embree runs the kernels of that instruction set whatever the CPU offers (neither
 * embreex nor embree_native.c takes a configuration string from the command line).
 *
 *   gcc -O2 -shared -fPIC -o embree_isa.so embree_isa.c -ldl
 *   EMBREE_ISA=avx2 LD_PRELOAD=./embree_isa.so python3 embree_anchor.py ...
 *
 * The real rtcNewDevice is found among the loaded objects (embreex loads its Embree
 * privately, out of RTLD_NEXT's reach).
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <link.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void *(*new_device_fn)(const char *);

static new_device_fn found;

static int find_embree(struct dl_phdr_info *info, size_t size, void *data)
{
    (void)size;
    (void)data;
    if (!info->dlpi_name || !strstr(info->dlpi_name, "libembree"))
        return 0;
    void *lib = dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD);
    if (lib)
        found = (new_device_fn)dlsym(lib, "rtcNewDevice");
    return found != NULL;
}

void *rtcNewDevice(const char *config)
{
    if (!found)
        dl_iterate_phdr(find_embree, NULL);
    if (!found) {
        fprintf(stderr, "embree_isa: no libembree loaded\n");
        abort();
    }
    const char *isa = getenv("EMBREE_ISA");
    if (!isa || !*isa)
        return found(config);
    char buffer[512];
    snprintf(buffer, sizeof buffer, "%s%sisa=%s", config ? config : "", config && *config ? "," : "", isa);
    return found(buffer);
}
