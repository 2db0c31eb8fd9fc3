# sitlnet in a container: Debian 12, the project's own setup and build, then its tests.
#   docker build -t sitlnet .            (podman build works the same)
#   docker run --rm --cap-drop ALL --cap-add NET_ADMIN --cap-add SYS_ADMIN \
#     --device /dev/net/tun -e SITLNET_MIN_CAPS=1 sitlnet
# NET_ADMIN creates the namespaces' veth and TAP devices and their addresses; SYS_ADMIN
# enters namespaces (setns), mounts /run/netns and the robots' sandboxes; /dev/net/tun is
# where TAPs come from. SITLNET_MIN_CAPS=1 says that no other capability is there, so a
# check that needs one skips and says so. scripts/container-test builds and runs this with
# podman or docker; docs/containers.md says why each option is there. It builds only the
# first stage, `packages`, and runs the host's checkout and build in it (mounted at the same
# path): the second stage would compile the same sources again.
# BASE: the Debian 12 image to start from; scripts/container-test passes one it made with
# debootstrap where no registry is reachable.
ARG BASE=debian:12
FROM ${BASE} AS packages
ENV DEBIAN_FRONTEND=noninteractive
# npm trusts the system's certificate authorities too (a local one included).
ENV NODE_EXTRA_CA_CERTS=/etc/ssl/certs/ca-certificates.crt
# Under /tmp, as many CI systems check out: a robot's sandbox keeps /tmp private, and robots still
# see sitlnet's own files there (docs/robot-images.md).
WORKDIR /tmp/sitlnet
# The packages first, in a layer of their own: a change to the sources does not install
# them again.
COPY scripts/setup scripts/setup
COPY tests/node_mavlink/package.json tests/node_mavlink/package-lock.json tests/node_mavlink/
RUN apt-get update -qq && apt-get install -y -qq --no-install-recommends ca-certificates >/dev/null \
    && scripts/setup --no-build
# The project, compiled in the image.
FROM packages
COPY . .
# Compiled once here: a ccache folder in the image would only make it larger.
ENV CCACHE_DISABLE=1
RUN scripts/setup
# `sitlnet` by name, as deploy/kubernetes/ calls it.
ENV PATH=/tmp/sitlnet/build/bin:$PATH
ENV CI=true
CMD ["scripts/test"]
