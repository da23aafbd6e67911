# trisnap on Debian 12: build in one stage, run from a slim image with only the runtime libraries.
#   docker build -t trisnap .
#   docker run --rm -v "$PWD:/data" trisnap snap /data/in.gpkg /data/out.gpkg --tolerance 0.01
# Not built on the development machine (no container engine there); see README "Install".

FROM debian:12 AS build
WORKDIR /src
COPY scripts/install_deps.sh scripts/install_deps.sh
RUN bash scripts/install_deps.sh && rm -rf /var/lib/apt/lists/*
COPY . .
RUN cmake --preset release -DTRISNAP_BUILD_TESTS=OFF -DTRISNAP_BUILD_BENCH=OFF \
    && cmake --build --preset release --target trisnap trisnap_docs \
    && cmake --install build/release --prefix /opt/trisnap \
    && /opt/trisnap/bin/trisnap --version

FROM debian:12-slim
# The package of every shared library the binary NEEDs (readelf -d, dpkg -S): GDAL, oneTBB, GMP (the engine's exact crossings), toml++ (settings files), spdlog and fmt; libc,
# libstdc++ and libgcc come with the base image. The test docker_runtime (tests/cli) checks this
# list against the built binary. bash-completion is left out: a container runs commands, not a shell.
RUN apt-get update \
    && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
       libgdal32 libsqlite3-0 libtbb12 libgmp10 libtomlplusplus3 libspdlog1.10 libfmt9 man-db \
    && rm -rf /var/lib/apt/lists/*
COPY --from=build /opt/trisnap /usr/local
RUN trisnap --version
WORKDIR /data
ENTRYPOINT ["trisnap"]
CMD ["--help"]
