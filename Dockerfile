# sitlnet in a container: Debian 12, the project's own setup, then its tests.
#   docker build -t sitlnet .
#   docker run --rm --cap-add NET_ADMIN --cap-add SYS_ADMIN --device /dev/net/tun \
#     --security-opt apparmor=unconfined sitlnet
# NET_ADMIN creates TAP/veth devices and addresses; SYS_ADMIN is needed for
# unshare/setns and the /run/netns bind mounts; /dev/net/tun for the TAPs.
FROM debian:12
ENV DEBIAN_FRONTEND=noninteractive
RUN apt-get update -qq && apt-get install -y -qq --no-install-recommends sudo ca-certificates \
    && rm -rf /var/lib/apt/lists/*
WORKDIR /src/sitlnet
COPY . .
RUN scripts/setup
ENV CI=true
CMD ["scripts/test"]
