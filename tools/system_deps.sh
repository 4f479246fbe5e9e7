#!/usr/bin/env bash
# The system servers the tests start for real (DESIGN: real servers, not mocks): Debian's
# mosquitto (the fleet's MQTT broker) and PostgreSQL (initdb/pg_ctl for the fleet's records),
# and the browser the web console's tests drive (Debian's chromium, through Playwright; only
# POLYNAV_SKIP_BROWSER=1 does without it, and then tests/web is skipped, saying so).
# Installs the missing ones with apt-get when it can (root, or sudo without a password);
# otherwise says what to install and fails.
set -euo pipefail
missing=()
command -v mosquitto >/dev/null 2>&1 || [ -x /usr/sbin/mosquitto ] || missing+=(mosquitto)
command -v mosquitto_sub >/dev/null 2>&1 || missing+=(mosquitto-clients)
if ! command -v initdb >/dev/null 2>&1 && ! ls /usr/lib/postgresql/*/bin/initdb >/dev/null 2>&1; then
    missing+=(postgresql)
fi
if [ "${POLYNAV_SKIP_BROWSER:-}" != "1" ] && ! command -v chromium >/dev/null 2>&1 \
        && [ ! -x /usr/bin/chromium ]; then
    missing+=(chromium)
fi
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -eq 0 ]; then
    sudo=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    sudo=(sudo -n)
else
    echo "the tests need: ${missing[*]} (Debian packages); install them, e.g. sudo apt-get install ${missing[*]}" >&2
    case " ${missing[*]} " in
        *" chromium "*) echo "(chromium is the browser of the web console's tests; POLYNAV_SKIP_BROWSER=1 skips those tests instead)" >&2 ;;
    esac
    exit 1
fi
echo "installing ${missing[*]} (apt-get) for the tests" >&2
"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q >&2
"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}" >&2 || {
    echo "could not install ${missing[*]} with apt-get (above: why); the tests need them" >&2
    exit 1
}
