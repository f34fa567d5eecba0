/*
 * sphctl and CURVE: where the keys come from, the CURVE options of a socket, the socket monitor
 * that tells a refused handshake from a server that does not answer, and `sphctl keygen`.
 *
 * Each setting comes from the first of: the option, the environment, the config file
 * ($XDG_CONFIG_HOME/sphctl/config, else ~/.config/sphctl/config; `name = value` lines, '#'
 * comments):
 *   endpoint     --endpoint    SPHD_ENDPOINT
 *   server_key   --server-key  SPHD_SERVER_KEY   sphd's public key: Z85 text or a file holding it
 *   key          --key         SPHCTL_KEY        this client's secret key file (client.key in the
 *                                                config directory when it exists)
 * CURVE is on when a server key is known.
 */
#include "sphctl.h"

#include "sph_fileio.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zmq.h>

#define Z85_LEN 40

int sphctl_config_dir(char *out, size_t n)
{
    const char *xdg = getenv("XDG_CONFIG_HOME"), *home = getenv("HOME");
    int len;
    if (xdg && *xdg)
        len = snprintf(out, n, "%s/sphctl", xdg);
    else if (home && *home)
        len = snprintf(out, n, "%s/.config/sphctl", home);
    else
        return -1;
    return len < 0 || (size_t)len >= n ? -1 : 0;
}

static char *trim(char *s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\n' || s[n - 1] == '\r'))
        s[--n] = '\0';
    return s;
}

/* The value of name in the config file, into out; 1 found, 0 not, -1 a bad line (said). */
static int config_get(const char *name, char *out, size_t n)
{
    char dir[1024], path[1100];
    if (sphctl_config_dir(dir, sizeof dir))
        return 0;
    snprintf(path, sizeof path, "%s/config", dir);
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    char line[2048];
    int found = 0, lineno = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char *l = trim(line);
        if (!*l || *l == '#')
            continue;
        char *eq = strchr(l, '=');
        if (!eq) {
            fprintf(stderr, "sphctl: %s:%d: not 'name = value'\n", path, lineno);
            fclose(f);
            return -1;
        }
        *eq = '\0';
        if (strcmp(trim(l), name) == 0) {
            char *v = trim(eq + 1);
            /* a relative file name is relative to the config directory */
            if (strcmp(name, "endpoint") != 0 && *v && *v != '/' && strlen(v) != Z85_LEN)
                snprintf(out, n, "%s/%s", dir, v);
            else
                snprintf(out, n, "%s", v);
            found = 1;
        }
    }
    fclose(f);
    return found;
}

/* A key from Z85 text (40 characters) or from the file that holds it. Returns 0 or -1 (said). */
static int load_key(const char *what, const char *src, char z85[Z85_LEN + 1])
{
    char buf[128];
    const char *text = src;
    if (strlen(src) != Z85_LEN || access(src, F_OK) == 0) {
        FILE *f = fopen(src, "r");
        if (!f) {
            fprintf(stderr, "sphctl: cannot read the %s '%s': %s\n", what, src, strerror(errno));
            return -1;
        }
        size_t n = fread(buf, 1, sizeof buf - 1, f);
        fclose(f);
        if (n == sizeof buf - 1) {
            fprintf(stderr, "sphctl: the %s file '%s' is too long for one key\n", what, src);
            return -1;
        }
        buf[n] = '\0';
        text = trim(buf);
        while (*text == '\n' || *text == '\r')
            text++;
    }
    unsigned char raw[32];
    if (strlen(text) != Z85_LEN || !zmq_z85_decode(raw, text)) {
        fprintf(stderr, "sphctl: the %s in '%s' is not a Z85 key of 40 characters\n", what, src);
        return -1;
    }
    memcpy(z85, text, Z85_LEN);
    z85[Z85_LEN] = '\0';
    return 0;
}

int sphctl_settings(sphctl *c, const char *endpoint, const char *server_key, const char *key)
{
    char buf[2048];
    const char *env;
    if (endpoint)
        snprintf(c->endpoint, sizeof c->endpoint, "%s", endpoint);
    else if ((env = getenv("SPHD_ENDPOINT")) && *env)
        snprintf(c->endpoint, sizeof c->endpoint, "%s", env);
    else {
        int r = config_get("endpoint", buf, sizeof buf);
        if (r < 0)
            return SPHCTL_EX_CONFIG;
        if (r > 0) {
            if (strlen(buf) >= sizeof c->endpoint) {
                fputs("sphctl: the config file's endpoint is too long\n", stderr);
                return SPHCTL_EX_CONFIG;
            }
            memcpy(c->endpoint, buf, strlen(buf) + 1);
        } else if (sph_default_control_endpoint(c->endpoint, sizeof c->endpoint)) {
            fputs("sphctl: cannot work out the default endpoint; use --endpoint\n", stderr);
            return SPHCTL_EX_USAGE;
        }
    }
    const char *sk = server_key;
    if (!sk && (env = getenv("SPHD_SERVER_KEY")) && *env)
        sk = env;
    if (!sk) {
        int r = config_get("server_key", buf, sizeof buf);
        if (r < 0)
            return SPHCTL_EX_CONFIG;
        if (r > 0)
            sk = buf;
    }
    if (!sk)
        return 0; /* no CURVE */
    if (load_key("server key", sk, c->server_key))
        return SPHCTL_EX_CONFIG;
    const char *kf = key;
    char kbuf[2048];
    if (!kf && (env = getenv("SPHCTL_KEY")) && *env)
        kf = env;
    if (!kf) {
        int r = config_get("key", kbuf, sizeof kbuf);
        if (r < 0)
            return SPHCTL_EX_CONFIG;
        if (r > 0)
            kf = kbuf;
    }
    if (!kf) {
        char dir[1024];
        if (sphctl_config_dir(dir, sizeof dir) == 0) {
            snprintf(kbuf, sizeof kbuf, "%s/client.key", dir);
            kf = kbuf;
        }
    }
    if (!kf || access(kf, F_OK) != 0) {
        fprintf(stderr,
                "sphctl: a server key is set but this client has no key of its own%s%s; make one "
                "with 'sphctl keygen' and have sphd's operator add the .pub file to its "
                "clients/\n",
                kf ? " (no " : "", kf ? kf : "");
        if (kf)
            fputs(")", stderr);
        return SPHCTL_EX_CONFIG;
    }
    if (load_key("secret key", kf, c->secret_key))
        return SPHCTL_EX_CONFIG;
    if (zmq_curve_public(c->public_key, c->secret_key) != 0) {
        fprintf(stderr, "sphctl: cannot derive the public key of %s: %s\n", kf,
                zmq_strerror(errno));
        return SPHCTL_EX_CONFIG;
    }
    c->curve = 1;
    return 0;
}

int sphctl_secure(sphctl *c, void *sock)
{
    if (!c->curve)
        return 0;
    if (zmq_setsockopt(sock, ZMQ_CURVE_SERVERKEY, c->server_key, Z85_LEN) != 0 ||
        zmq_setsockopt(sock, ZMQ_CURVE_PUBLICKEY, c->public_key, Z85_LEN) != 0 ||
        zmq_setsockopt(sock, ZMQ_CURVE_SECRETKEY, c->secret_key, Z85_LEN) != 0) {
        fprintf(stderr, "sphctl: cannot set the CURVE keys: %s\n", zmq_strerror(errno));
        return -1;
    }
    return 0;
}

void *sphctl_monitor(sphctl *c, void *sock, const char *name)
{
    char ep[64];
    snprintf(ep, sizeof ep, "inproc://sphctl-monitor-%s", name);
    if (zmq_socket_monitor(sock, ep,
                           ZMQ_EVENT_HANDSHAKE_FAILED_AUTH | ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL |
                               ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL |
                               ZMQ_EVENT_HANDSHAKE_SUCCEEDED) != 0)
        return NULL;
    void *mon = zmq_socket(c->ctx, ZMQ_PAIR);
    int zero = 0;
    if (!mon || zmq_setsockopt(mon, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        zmq_connect(mon, ep) != 0) {
        if (mon)
            zmq_close(mon);
        return NULL;
    }
    return mon;
}

int sphctl_refused(sphctl *c, void *mon, const char *ep)
{
    return sphctl_monitor_read(c, mon, ep, NULL);
}

int sphctl_monitor_read(sphctl *c, void *mon, const char *ep, int *connected)
{
    int refused = 0;
    for (;;) {
        zmq_msg_t m;
        zmq_msg_init(&m);
        if (zmq_msg_recv(&m, mon, ZMQ_DONTWAIT) < 0) {
            zmq_msg_close(&m);
            return refused;
        }
        uint16_t event = 0;
        uint32_t value = 0;
        if (zmq_msg_size(&m) >= 6) {
            memcpy(&event, zmq_msg_data(&m), 2);
            memcpy(&value, (const char *)zmq_msg_data(&m) + 2, 4);
        }
        int more = zmq_msg_more(&m);
        zmq_msg_close(&m);
        while (more) { /* the endpoint frame */
            zmq_msg_init(&m);
            more = zmq_msg_recv(&m, mon, 0) >= 0 && zmq_msg_more(&m);
            zmq_msg_close(&m);
        }
        if (event == ZMQ_EVENT_HANDSHAKE_SUCCEEDED && connected)
            *connected = 1;
        if (refused)
            continue;
        if (event == ZMQ_EVENT_HANDSHAKE_FAILED_AUTH) {
            fprintf(stderr,
                    "sphctl: sphd at %s refused this client: its key %s is not authorised (ask "
                    "sphd's operator to add it to the server's clients/ directory)\n",
                    ep, c->curve ? c->public_key : "(none)");
            refused = 1;
        } else if (event == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL ||
                   event == ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL) {
            /* a plain client meets a CURVE server that hangs up (or says "mechanism
             * mismatch"); a CURVE client with the wrong server key, likewise */
            if (!c->curve)
                fprintf(stderr,
                        "sphctl: sphd at %s refused a plain connection: it requires CURVE; give "
                        "its public key (--server-key, SPHD_SERVER_KEY or server_key in the "
                        "config file) and a key of this client's (sphctl keygen)\n",
                        ep);
            else if (event == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL &&
                     value == ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH)
                fprintf(stderr,
                        "sphctl: sphd at %s does not use CURVE: drop the server key to talk to "
                        "it\n",
                        ep);
            else
                fprintf(stderr,
                        "sphctl: the CURVE handshake with sphd at %s failed: is %s its public "
                        "key?\n",
                        ep, c->server_key);
            refused = 1;
        }
    }
}

/* Writes a key file with mode (replacing it). Returns 0 or -1 (said). */
static int write_key(const char *path, const char *z85, mode_t mode)
{
    char text[Z85_LEN + 2];
    snprintf(text, sizeof text, "%s\n", z85);
    if (sph_write_atomic(path, text, strlen(text), mode) != 0 || chmod(path, mode) != 0) {
        fprintf(stderr, "sphctl: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

int sphctl_cmd_keygen(sphctl *c, int argc, char **argv)
{
    (void)c;
    static const char help[] =
        "Usage: sphctl keygen [--out PATH] [--force]\n"
        "Makes a CURVE key pair: PATH.key, the secret key (mode 600: keep it), and PATH.pub,\n"
        "the public key (give it to sphd's operator, who puts it in the server's clients/\n"
        "directory). PATH defaults to $XDG_CONFIG_HOME/sphctl/client (~/.config/sphctl/client),\n"
        "where sphctl looks for its key. Also makes a server's key pair: --out DIR/server for\n"
        "'sphd --curve DIR'. Prints the public key.\n"
        "  --force   replace existing key files\n";
    enum { OUT, FORCE, NOPTS };
    static const struct option lo[] = {{"out", required_argument, NULL, OUT},
                                       {"force", no_argument, NULL, FORCE},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
    static const sphctl_argspec spec = {
        help, "h", lo, "bad option", 0, 0, "keygen takes no argument"};
    const char *opt[NOPTS] = {NULL};
    int rc = sphctl_args(&spec, argc, argv, sphctl_store_opt, opt);
    if (rc != SPHCTL_RUN)
        return rc;
    char base[2048];
    if (opt[OUT]) {
        snprintf(base, sizeof base, "%s", opt[OUT]);
    } else {
        char dir[1024];
        if (sphctl_config_dir(dir, sizeof dir)) {
            fputs("sphctl: neither XDG_CONFIG_HOME nor HOME is set; use --out\n", stderr);
            return SPHCTL_EX_USAGE;
        }
        if (sph_mkdirs(dir, 0700) != 0) {
            fprintf(stderr, "sphctl: cannot create %s: %s\n", dir, strerror(errno));
            return SPHCTL_EX_CANTCREAT;
        }
        snprintf(base, sizeof base, "%s/client", dir);
    }
    char pub[Z85_LEN + 1], sec[Z85_LEN + 1];
    if (zmq_curve_keypair(pub, sec) != 0) {
        fprintf(stderr, "sphctl: cannot make a key pair: %s\n", zmq_strerror(errno));
        return SPHCTL_EX_SOFTWARE;
    }
    char kpath[2100], ppath[2100];
    snprintf(kpath, sizeof kpath, "%s.key", base);
    snprintf(ppath, sizeof ppath, "%s.pub", base);
    const int force = opt[FORCE] != NULL;
    if (!force && (access(kpath, F_OK) == 0 || access(ppath, F_OK) == 0)) {
        fprintf(stderr, "sphctl: %s or %s exists; keep them, or replace them with --force\n", kpath,
                ppath);
        return SPHCTL_EX_CANTCREAT;
    }
    if (write_key(kpath, sec, 0600) != 0 || write_key(ppath, pub, 0644) != 0)
        return SPHCTL_EX_CANTCREAT;
    memset(sec, 0, sizeof sec);
    if (c->json) {
        json_t *r = json_pack("{s:s, s:s, s:s}", "public_key", pub, "secret_file", kpath,
                              "public_file", ppath);
        sphctl_print_json(r, 1);
        json_decref(r);
    } else {
        printf("%s\n", pub);
        fprintf(stderr, "sphctl: secret key in %s (mode 600), public key in %s\n", kpath, ppath);
    }
    return 0;
}
