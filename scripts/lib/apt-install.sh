# shellcheck shell=bash
# apt_install WHAT PACKAGE...: installs Debian/Ubuntu packages with apt-get, as root or through
# passwordless sudo, waiting up to 5 minutes for another apt to finish. Source this file.
# Returns 1 with the reason on stderr (and the end of apt-get's output) when it cannot
# install; WHAT names the missing thing in messages.
apt_install() {
    local what=$1
    shift
    local as_root=() log status
    if ! command -v apt-get >/dev/null 2>&1; then
        echo "cannot install $what: no apt-get on this system (Debian packages: $*)" >&2
        return 1
    fi
    if [ "$(id -u)" -ne 0 ]; then
        if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
            as_root=(sudo -n)
        else
            echo "cannot install $what: apt-get needs root and passwordless sudo is not available" \
                "(run: sudo apt-get install $*)" >&2
            return 1
        fi
    fi
    echo "installing $what with apt-get: $*" >&2
    log=$(mktemp)
    status=0
    {
        "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
            "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
                apt-get install -y -qq --no-install-recommends -o DPkg::Lock::Timeout=300 "$@"
    } >"$log" 2>&1 || status=$?
    if [ "$status" -ne 0 ]; then
        echo "cannot install $what: apt-get failed (exit $status); its last lines:" >&2
        tail -n 15 "$log" >&2
    fi
    rm -f "$log"
    return "$status"
}
