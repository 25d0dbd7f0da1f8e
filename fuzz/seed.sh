#!/usr/bin/env bash
# Seeds the fuzz targets' corpora (fuzz/corpus/TARGET, ignored by git) with the test
# scenes, the examples and, when ../shared is beside the checkout, the P3F course
# scenes and BART's AFF files; links BART's scene files and textures into
# corpus/aff-files, where the aff target's inputs find their includes. Nothing from
# ../shared enters the repository: the corpus is made here, at run time.
set -euo pipefail
cd "$(dirname "$0")"
shared=${NFFRT_SHARED:-../../shared}
mkdir -p corpus/parse corpus/parse_render corpus/p3f corpus/aff corpus/aff-files
cp ../tests/data/ok/*.nff ../tests/data/bad/*.nff ../examples/*.nff corpus/parse/
cp ../tests/data/ok/*.nff ../examples/*.nff corpus/parse_render/
cp ../examples/*.p3f corpus/p3f/
cp ../tests/data/ok/*.p3f ../tests/data/bad/*.p3f corpus/p3f/ 2>/dev/null || true
if [ -d "$shared/scenes" ]; then
    # The course's scenes under 64 KiB (the larger ones only repeat their entities).
    find "$shared/scenes/p3f" -name '*.p3f' -size -64k -exec cp {} corpus/p3f/ \;
    for scene in "$shared"/scenes/bart/*/; do
        for f in "$scene"aff/*.aff "$scene"TextureFiles/*.ppm; do
            [ -e "corpus/aff-files/$(basename "$f")" ] || ln -s "$(cd "$(dirname "$f")" && pwd)/$(basename "$f")" corpus/aff-files/
        done
        # Each scene file is a seed; those over 64 KiB are meshes that only repeat.
        find "$scene"aff -name '*.aff' -size -64k -exec cp {} corpus/aff/ \;
    done
else
    echo "seed.sh: $shared is absent: no P3F course scenes and no AFF files (the aff target needs them)" >&2
fi
for target in parse parse_render p3f aff; do
    echo "corpus/$target: $(ls corpus/$target | wc -l) inputs"
done
