#include "sphd_curve.h"

#include "sphd.h"
#include "sphd_daemon.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zmq.h>

#define ZAP_ENDPOINT "inproc://zeromq.zap.01"
#define ZAP_DOMAIN   "sphd"
#define ZAP_RUNNERS  "sphd-runners" /* the runners' socket: the runner key only */
#define KEY_Z85_LEN  40
#define KEY_FILE_MAX 256

typedef struct client_key {
    unsigned char key[32];
    char z85[KEY_Z85_LEN + 1];
    char name[KEY_FILE_MAX]; /* the file's name, for the log */
} client_key;

struct sphd_curve {
    char dir[SPHD_PATH_MAX];
    unsigned char secret[32];
    char public_z85[KEY_Z85_LEN + 1];
    client_key *clients;
    int nclients;
    void *zap;
    int has_runner;
    client_key runner; /* the key pair of the runners (sphd_curve_runner_keys) */
};

/* Reads one Z85 key from a file: 40 characters, surrounding white space allowed. Returns 0, or
 * -1 with why set. */
static int read_key_file(const char *path, char z85[KEY_Z85_LEN + 1], unsigned char key[32],
                         const char **why)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        *why = strerror(errno);
        return -1;
    }
    char buf[128];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    if (n == sizeof buf - 1) {
        *why = "too long for one key";
        return -1;
    }
    buf[n] = '\0';
    char *p = buf;
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        p++;
    size_t len = strcspn(p, " \t\r\n");
    char *rest = p + len;
    while (*rest == ' ' || *rest == '\t' || *rest == '\n' || *rest == '\r')
        rest++;
    if (len != KEY_Z85_LEN || *rest) {
        *why = "not one Z85 key of 40 characters";
        return -1;
    }
    memcpy(z85, p, KEY_Z85_LEN);
    z85[KEY_Z85_LEN] = '\0';
    if (!zmq_z85_decode(key, z85)) {
        *why = "not Z85";
        return -1;
    }
    return 0;
}

/* Reads DIR/clients/ into a new list. Returns 0 or -1 (logged). */
static int read_clients(const char *dir, client_key **out, int *nout)
{
    char path[SPHD_PATH_MAX + 16];
    snprintf(path, sizeof path, "%s/clients", dir);
    DIR *dd = opendir(path);
    if (!dd) {
        sphd_log("CURVE: cannot read the authorised keys in %s: %s", path, strerror(errno));
        return -1;
    }
    client_key *keys = NULL;
    int n = 0, cap = 0;
    struct dirent *e;
    while ((e = readdir(dd))) {
        if (e->d_name[0] == '.' || strlen(e->d_name) >= KEY_FILE_MAX)
            continue;
        char file[SPHD_PATH_MAX + KEY_FILE_MAX + 32];
        snprintf(file, sizeof file, "%s/%s", path, e->d_name);
        struct stat st;
        if (stat(file, &st) != 0 || !S_ISREG(st.st_mode))
            continue;
        if (n == cap) {
            cap = cap ? 2 * cap : 16;
            client_key *nk = realloc(keys, (size_t)cap * sizeof *nk);
            if (!nk) {
                free(keys);
                closedir(dd);
                sphd_log("CURVE: out of memory reading %s", path);
                return -1;
            }
            keys = nk;
        }
        const char *why = NULL;
        if (read_key_file(file, keys[n].z85, keys[n].key, &why) != 0) {
            sphd_log("CURVE: ignoring %s: %s", file, why);
            continue;
        }
        snprintf(keys[n].name, sizeof keys[n].name, "%s", e->d_name);
        n++;
    }
    closedir(dd);
    *out = keys;
    *nout = n;
    return 0;
}

sphd_curve *sphd_curve_load(const char *dir)
{
    if (!zmq_has("curve")) {
        fprintf(stderr, "sphd: this libzmq was built without CURVE; --curve is not available\n");
        return NULL;
    }
    sphd_curve *cv = calloc(1, sizeof *cv);
    if (!cv)
        return NULL;
    snprintf(cv->dir, sizeof cv->dir, "%s", dir);
    char path[SPHD_PATH_MAX + 16];
    snprintf(path, sizeof path, "%s/server.key", dir);
    struct stat st;
    const char *why = NULL;
    char z85[KEY_Z85_LEN + 1];
    if (stat(path, &st) != 0) {
        fprintf(stderr,
                "sphd: --curve %s: no server key %s (%s); make one with 'sphctl keygen --out "
                "%s/server' and put the clients' public keys in %s/clients/\n",
                dir, path, strerror(errno), dir, dir);
        free(cv);
        return NULL;
    }
    if ((st.st_mode & 077) != 0) {
        fprintf(stderr,
                "sphd: --curve %s: the secret key %s can be read by others (mode %03o); "
                "chmod 600 it\n",
                dir, path, (unsigned)(st.st_mode & 0777));
        free(cv);
        return NULL;
    }
    if (read_key_file(path, z85, cv->secret, &why) != 0) {
        fprintf(stderr, "sphd: --curve %s: %s: %s\n", dir, path, why);
        free(cv);
        return NULL;
    }
    if (zmq_curve_public(cv->public_z85, z85) != 0) {
        fprintf(stderr, "sphd: --curve %s: cannot derive the public key: %s\n", dir,
                zmq_strerror(errno));
        free(cv);
        return NULL;
    }
    memset(z85, 0, sizeof z85);
    if (read_clients(dir, &cv->clients, &cv->nclients) != 0) {
        fprintf(stderr,
                "sphd: --curve %s: make %s/clients/ and put the clients' public keys "
                "there, one file each\n",
                dir, dir);
        sphd_curve_free(cv);
        return NULL;
    }
    return cv;
}

int sphd_curve_start(sphd_curve *cv, void *ctx)
{
    cv->zap = zmq_socket(ctx, ZMQ_REP);
    int zero = 0;
    if (!cv->zap || zmq_setsockopt(cv->zap, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        zmq_bind(cv->zap, ZAP_ENDPOINT) != 0) {
        sphd_log("CURVE: cannot start the ZAP handler: %s", zmq_strerror(errno));
        return -1;
    }
    sphd_log("CURVE on: server public key %s, %d authorised client key(s) in %s/clients",
             cv->public_z85, cv->nclients, cv->dir);
    return 0;
}

void *sphd_curve_zap_socket(const sphd_curve *cv)
{
    return cv->zap;
}

static int write_key(const char *path, const char *z85)
{
    char text[KEY_Z85_LEN + 2];
    snprintf(text, sizeof text, "%s\n", z85);
    return sphd_write_atomic(path, text, strlen(text)) != 0 || chmod(path, 0600) != 0 ? -1 : 0;
}

int sphd_curve_runner_keys(sphd_curve *cv, const char *dir)
{
    char path[SPHD_PATH_MAX + 32], z85[KEY_Z85_LEN + 1], secret[KEY_Z85_LEN + 1];
    const char *why = NULL;
    if (sphd_mkdirs(dir) != 0 || chmod(dir, 0700) != 0) {
        sphd_log("CURVE: cannot make %s: %s", dir, strerror(errno));
        return -1;
    }
    snprintf(path, sizeof path, "%s/runner.key", dir);
    if (read_key_file(path, secret, cv->runner.key, &why) != 0) {
        /* none yet (or damaged): a new pair; runners started before use the old one */
        if (zmq_curve_keypair(z85, secret) != 0 || write_key(path, secret) != 0) {
            sphd_log("CURVE: cannot write %s: %s", path, strerror(errno));
            return -1;
        }
    }
    if (zmq_curve_public(z85, secret) != 0 || !zmq_z85_decode(cv->runner.key, z85)) {
        sphd_log("CURVE: %s: cannot derive its public key", path);
        return -1;
    }
    memset(secret, 0, sizeof secret);
    snprintf(cv->runner.z85, sizeof cv->runner.z85, "%s", z85);
    snprintf(cv->runner.name, sizeof cv->runner.name, "runner");
    snprintf(path, sizeof path, "%s/runner.pub", dir);
    if (write_key(path, z85) != 0)
        return -1;
    snprintf(path, sizeof path, "%s/server.pub", dir);
    if (write_key(path, cv->public_z85) != 0)
        return -1;
    cv->has_runner = 1;
    return 0;
}

int sphd_curve_runners_server(const sphd_curve *cv, void *s)
{
    int one = 1;
    if (zmq_setsockopt(s, ZMQ_CURVE_SERVER, &one, sizeof one) != 0 ||
        zmq_setsockopt(s, ZMQ_CURVE_SECRETKEY, cv->secret, sizeof cv->secret) != 0 ||
        zmq_setsockopt(s, ZMQ_ZAP_DOMAIN, ZAP_RUNNERS, strlen(ZAP_RUNNERS)) != 0)
        return -1;
    return 0;
}

int sphd_curve_server(const sphd_curve *cv, void *s)
{
    int one = 1;
    if (zmq_setsockopt(s, ZMQ_CURVE_SERVER, &one, sizeof one) != 0 ||
        zmq_setsockopt(s, ZMQ_CURVE_SECRETKEY, cv->secret, sizeof cv->secret) != 0 ||
        zmq_setsockopt(s, ZMQ_ZAP_DOMAIN, ZAP_DOMAIN, strlen(ZAP_DOMAIN)) != 0)
        return -1;
    return 0;
}

static const client_key *find_key(const sphd_curve *cv, const unsigned char key[32])
{
    for (int i = 0; i < cv->nclients; i++)
        if (memcmp(cv->clients[i].key, key, 32) == 0)
            return &cv->clients[i];
    return NULL;
}

int sphd_curve_authorised(const sphd_curve *cv, const char *z85)
{
    for (int i = 0; z85 && i < cv->nclients; i++)
        if (strcmp(cv->clients[i].z85, z85) == 0)
            return 1;
    return 0;
}

const char *sphd_curve_public(const sphd_curve *cv)
{
    return cv->public_z85;
}

/* One ZAP request (RFC 27): version, request id, domain, address, identity, mechanism,
 * credentials; the reply: version, request id, status code, status text, user id, metadata. */
static void answer_one(sphd_curve *cv)
{
    enum { NPARTS = 8 };
    zmq_msg_t part[NPARTS];
    int n = 0, more = 1;
    while (more) {
        zmq_msg_t m;
        zmq_msg_init(&m);
        if (zmq_msg_recv(&m, cv->zap, ZMQ_DONTWAIT) < 0) {
            zmq_msg_close(&m);
            if (errno == EINTR)
                continue;
            break;
        }
        more = zmq_msg_more(&m);
        if (n < NPARTS)
            part[n++] = m;
        else
            zmq_msg_close(&m);
    }
    if (n == 0)
        return;
    const char *status = "400", *text = "malformed ZAP request";
    char user[KEY_Z85_LEN + 1] = "";
    char addr[64] = "?";
    if (n >= 6) {
        size_t al = zmq_msg_size(&part[3]);
        snprintf(addr, sizeof addr, "%.*s", (int)(al < 63 ? al : 63),
                 (const char *)zmq_msg_data(&part[3]));
        const char *mech = zmq_msg_data(&part[5]);
        size_t ml = zmq_msg_size(&part[5]);
        const int runners_domain =
            zmq_msg_size(&part[2]) == strlen(ZAP_RUNNERS) &&
            memcmp(zmq_msg_data(&part[2]), ZAP_RUNNERS, strlen(ZAP_RUNNERS)) == 0;
        if (ml == 5 && memcmp(mech, "CURVE", 5) == 0 && n >= 7 && zmq_msg_size(&part[6]) == 32) {
            /* the clients' keys open the control and stream sockets, the runners' key only
             * the runners' socket */
            const client_key *k =
                runners_domain
                    ? (cv->has_runner && memcmp(cv->runner.key, zmq_msg_data(&part[6]), 32) == 0
                           ? &cv->runner
                           : NULL)
                    : find_key(cv, zmq_msg_data(&part[6]));
            if (k) {
                status = "200", text = "OK";
                snprintf(user, sizeof user, "%s", k->z85);
            } else {
                char z85[KEY_Z85_LEN + 1];
                zmq_z85_encode(z85, zmq_msg_data(&part[6]), 32);
                text = "client key not authorised";
                sphd_log("CURVE: refused a client from %s: key %s is not in %s/clients", addr, z85,
                         cv->dir);
            }
        } else {
            text = "CURVE required";
            sphd_log("CURVE: refused a client from %s: mechanism %.*s", addr, (int)ml, mech);
        }
    }
    /* the reply: the version and request id as they came, then ours */
    const void *ver = n > 0 ? zmq_msg_data(&part[0]) : "1.0";
    size_t verlen = n > 0 ? zmq_msg_size(&part[0]) : 3;
    const void *rid = n > 1 ? zmq_msg_data(&part[1]) : "";
    size_t ridlen = n > 1 ? zmq_msg_size(&part[1]) : 0;
    if (zmq_send(cv->zap, ver, verlen, ZMQ_SNDMORE) < 0 ||
        zmq_send(cv->zap, rid, ridlen, ZMQ_SNDMORE) < 0 ||
        zmq_send(cv->zap, status, 3, ZMQ_SNDMORE) < 0 ||
        zmq_send(cv->zap, text, strlen(text), ZMQ_SNDMORE) < 0 ||
        zmq_send(cv->zap, user, strlen(user), ZMQ_SNDMORE) < 0 || zmq_send(cv->zap, "", 0, 0) < 0)
        sphd_log("CURVE: cannot answer a ZAP request: %s", zmq_strerror(errno));
    for (int i = 0; i < n; i++)
        zmq_msg_close(&part[i]);
}

void sphd_curve_on_zap(sphd_curve *cv)
{
    for (int k = 0; k < 64; k++) {
        int ev = 0;
        size_t len = sizeof ev;
        if (zmq_getsockopt(cv->zap, ZMQ_EVENTS, &ev, &len) != 0 || !(ev & ZMQ_POLLIN))
            return;
        answer_one(cv);
    }
}

int sphd_curve_reload(sphd_curve *cv)
{
    client_key *keys;
    int n;
    if (read_clients(cv->dir, &keys, &n) != 0)
        return -1;
    int revoked = 0;
    for (int i = 0; i < cv->nclients; i++) {
        int still = 0;
        for (int j = 0; j < n && !still; j++)
            still = memcmp(cv->clients[i].key, keys[j].key, 32) == 0;
        if (!still) {
            revoked++;
            sphd_log("CURVE: key %s (%s) revoked", cv->clients[i].z85, cv->clients[i].name);
        }
    }
    free(cv->clients);
    cv->clients = keys;
    cv->nclients = n;
    sphd_log("CURVE: %d authorised client key(s) after reload, %d revoked", n, revoked);
    return revoked;
}

void sphd_curve_free(sphd_curve *cv)
{
    if (!cv)
        return;
    if (cv->zap)
        zmq_close(cv->zap);
    memset(cv->secret, 0, sizeof cv->secret);
    free(cv->clients);
    free(cv);
}
