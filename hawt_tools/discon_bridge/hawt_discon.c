/* libhawt_discon: a Bladed-style DISCON library whose controller is a hawt graph (issue 33).
 *
 *   void DISCON(float *avrSWAP, int *aviFAIL, char *accINFILE, char *avcOUTNAME, char *avcMSG);
 *
 * A simulator (OpenFAST's ServoDyn, hawt's own discon host) calls DISCON once per communication interval.
 * Each call sends the swap array's records 1-129 (every measurement of the interface) to a hawt bridge
 * process over a Unix domain socket (SOCK_SEQPACKET: one message per call, boundaries kept, a peer that dies
 * is seen at once as a closed connection) and writes the commands of that step back: pitch per blade
 * (records 42-44), collective pitch (45) and generator torque (47). The bridge steps the graph named in the
 * bridge file (accINFILE); hawt_tools/hawt_tools/discon_bridge.py is the other end and documents the file.
 *
 * The library reads three keys of the bridge file: `socket` (where the bridge listens), `start_timeout`
 * (seconds, default 60: how long the first call waits for the bridge to listen and to answer, while it builds
 * the graph) and `timeout` (seconds, default 10: how long every later call waits for its answer). Status 0
 * (first call) connects and sends the file's path; status -1 (last call) ends the bridge's run and closes the
 * connection.
 *
 * Safety. Whatever goes wrong (a bad bridge file, no bridge listening, no answer within the timeout, a bridge
 * that died or refused the graph), the call sets aviFAIL = -1 with a one-line message in avcMSG and returns
 * safe commands, as every later call does: each blade's last pitch command ramped towards feather at the
 * turbine's largest pitch rate (ROSCO's shutdown, SD_Mode), and the last generator torque held. Zero torque is
 * not safe: it drops the braking torque while the blades are still near fine pitch, and the rotor overspeeds.
 * The feather angle and rate are those the bridge names in its first answer (the graph's turbine), else the
 * simulator's records 7 and 9, else 90 deg and 8 deg/s.
 *
 * State lives in one static struct: one run per loaded image, as in ROSCO (a host loads a private copy per
 * instance).
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <poll.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

/* avrSWAP records (1-based; Bladed User Manual, Appendix A; OpenFAST ServoDyn Fill_avrSWAP). */
enum {
    R_STATUS = 1,              /* in: 0 first call, 1 running, -1 last call */
    R_TIME = 2,                /* in: simulation time [s] */
    R_DT = 3,                  /* in: communication interval [s] */
    R_PITCH_1 = 4,             /* in: measured pitch of blade 1 [rad] (blades 2, 3: records 33, 34) */
    R_MAX_PITCH = 7,           /* in: maximum pitch angle [rad] (0 if the simulator does not say) */
    R_MAX_PITCH_RATE = 9,      /* in: maximum pitch rate [rad/s] (0 if the simulator does not say) */
    R_GENERATOR_TORQUE = 23,   /* in: measured generator torque [N*m] */
    R_PITCH_2 = 33,
    R_PITCH_3 = 34,
    R_DEMANDED_PITCH_1 = 42,   /* out: pitch demand of blades 1-3, records 42-44 [rad] */
    R_DEMANDED_COLLECTIVE = 45,/* out: collective pitch demand [rad] */
    R_DEMANDED_TORQUE = 47,    /* out: generator torque demand [N*m] */
    R_MESSAGE_SIZE = 49,       /* in: characters of avcMSG, its NUL included */
    R_PITCH_OVERRIDE = 55,     /* out: 0 = the library commands pitch */
    R_TORQUE_OVERRIDE = 56,    /* out: 0 = the library commands torque */
    R_BLADES = 61,             /* in: number of blades */
};
#define SWAP(r) avrSWAP[(r) - 1]

#define SENT_RECORDS 129       /* records 1-129 go to the bridge */
#define PATH_CHARS 1024
#define MESSAGE_CHARS 1024
#define MAX_BLADES 3
#define DEFAULT_TIMEOUT 10.0          /* [s] */
#define DEFAULT_START_TIMEOUT 60.0    /* [s] */
#define DEFAULT_FEATHER_ANGLE 1.5707963 /* [rad], 90 deg */
#define DEFAULT_FEATHER_RATE 0.13962634 /* [rad/s], 8 deg/s */

/* The messages of the channel; hawt_tools/hawt_tools/discon_bridge.py has the same layouts (REQUEST, REPLY). */
struct request {
    char magic[4];             /* "HWB1" */
    int32_t status;            /* record 1 */
    float swap[SENT_RECORDS];  /* records 1-129 */
    char infile[PATH_CHARS];   /* the bridge file (first call only) */
};

struct reply {
    char magic[4];             /* "HWR1" */
    int32_t fail;              /* 0 ok, < 0 the bridge failed (message) */
    float pitch[MAX_BLADES];   /* records 42-44 [rad] */
    float collective;          /* record 45 [rad] */
    float torque;              /* record 47 [N*m] */
    float feather_angle;       /* the graph's turbine: largest pitch angle [rad] */
    float feather_rate;        /* and largest pitch rate [rad/s] */
    char message[MESSAGE_CHARS];
};

static struct {
    int fd;                    /* connection to the bridge, -1 before the first call and after the last */
    int failed;                /* set by the first failure: from then on, safe commands only */
    double timeout;            /* [s] bound on waiting for an answer */
    double start_timeout;      /* [s] bound on waiting for the bridge to listen and answer the first call */
    char socket_path[sizeof(((struct sockaddr_un *)0)->sun_path)];
    float pitch[MAX_BLADES];   /* last pitch command per blade [rad] */
    float torque;              /* last generator torque command [N*m] */
    float feather_angle, feather_rate;
    char failure[MESSAGE_CHARS];
} bridge = {.fd = -1};

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int blades_of(const float *avrSWAP)
{
    int b = (int)lroundf(SWAP(R_BLADES));
    return b < 1 || b > MAX_BLADES ? MAX_BLADES : b;
}

/* Remember the failure (the first one) for this and every later call; close the connection. */
__attribute__((format(printf, 1, 2))) static void fail(const char *format, ...)
{
    va_list arguments;
    if (bridge.failed)
        return;
    bridge.failed = 1;
    va_start(arguments, format);
    vsnprintf(bridge.failure, sizeof bridge.failure, format, arguments);
    va_end(arguments);
    if (bridge.fd >= 0)
        close(bridge.fd);
    bridge.fd = -1;
}

/* Read `socket`, `timeout` and `start_timeout` from the bridge file (`key = value` lines, # comments); 0 on success. */
static int read_bridge_file(const char *path)
{
    FILE *file = fopen(path, "r");
    char line[2048];
    bridge.timeout = DEFAULT_TIMEOUT;
    bridge.start_timeout = DEFAULT_START_TIMEOUT;
    bridge.socket_path[0] = '\0';
    if (!file) {
        fail("hawt bridge file %s: cannot read it: %s", path, strerror(errno));
        return -1;
    }
    while (fgets(line, sizeof line, file)) {
        char key[64], value[1024];
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        if (sscanf(line, " %63[^= \t] = %1023[^\n]", key, value) != 2)
            continue;
        for (char *end = value + strlen(value); end > value && (end[-1] == ' ' || end[-1] == '\t' ||
                                                                 end[-1] == '\r'); )
            *--end = '\0';
        if (strcmp(key, "socket") == 0) {
            if (strlen(value) >= sizeof bridge.socket_path) {
                fclose(file);
                fail("hawt bridge file %s: socket: a path of at most %zu characters", path,
                     sizeof bridge.socket_path - 1);
                return -1;
            }
            strcpy(bridge.socket_path, value);
        } else if (strcmp(key, "timeout") == 0 || strcmp(key, "start_timeout") == 0) {
            char *end;
            double seconds = strtod(value, &end);
            if (*end != '\0' || !(seconds > 0)) {
                fclose(file);
                fail("hawt bridge file %s: %s: expected seconds > 0, found %s", path, key, value);
                return -1;
            }
            *(strcmp(key, "timeout") == 0 ? &bridge.timeout : &bridge.start_timeout) = seconds;
        }
    }
    fclose(file);
    if (bridge.socket_path[0] == '\0') {
        fail("hawt bridge file %s: no socket = PATH line (where the hawt bridge listens)", path);
        return -1;
    }
    return 0;
}

/* Connect to the bridge, waiting up to the start timeout for it to listen; 0 on success. */
static int connect_bridge(void)
{
    struct sockaddr_un address = {.sun_family = AF_UNIX};
    double deadline = now() + bridge.start_timeout;
    strcpy(address.sun_path, bridge.socket_path);
    for (;;) {
        int fd = socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
        if (fd < 0) {
            fail("hawt bridge: cannot make a socket: %s", strerror(errno));
            return -1;
        }
        if (connect(fd, (struct sockaddr *)&address, sizeof address) == 0) {
            bridge.fd = fd;
            return 0;
        }
        int error = errno;
        close(fd);
        if ((error != ENOENT && error != ECONNREFUSED) || now() > deadline) {
            fail("no hawt bridge answers on %s within %g s (start it with: hawt bridge FILE)",
                 bridge.socket_path, bridge.start_timeout);
            return -1;
        }
        usleep(10000); /* the bridge is not listening yet: try again in 10 ms, until the deadline */
    }
}

/* Send this call's records, wait for the answer within the (start) timeout; 0 on success. */
static int exchange(const float *avrSWAP, const char *infile, struct reply *answer)
{
    struct request request = {.magic = {'H', 'W', 'B', '1'}, .status = (int32_t)lroundf(SWAP(R_STATUS))};
    memcpy(request.swap, avrSWAP, sizeof request.swap);
    if (request.status == 0)
        snprintf(request.infile, sizeof request.infile, "%s", infile);
    if (send(bridge.fd, &request, sizeof request, MSG_NOSIGNAL) != (ssize_t)sizeof request) {
        fail("the hawt bridge on %s is gone (it closed the connection) at t = %g s", bridge.socket_path,
             (double)SWAP(R_TIME));
        return -1;
    }
    struct pollfd ready = {.fd = bridge.fd, .events = POLLIN};
    double timeout = request.status == 0 ? bridge.start_timeout : bridge.timeout;
    int polled;
    do
        polled = poll(&ready, 1, (int)ceil(timeout * 1000));
    while (polled < 0 && errno == EINTR);
    if (polled == 0) {
        fail("the hawt bridge on %s did not answer within %g s at t = %g s", bridge.socket_path, timeout,
             (double)SWAP(R_TIME));
        return -1;
    }
    ssize_t got = recv(bridge.fd, answer, sizeof *answer, 0);
    if (got <= 0) {
        fail("the hawt bridge on %s is gone (it closed the connection) at t = %g s", bridge.socket_path,
             (double)SWAP(R_TIME));
        return -1;
    }
    if (got != (ssize_t)sizeof *answer || memcmp(answer->magic, "HWR1", 4) != 0) {
        fail("the hawt bridge on %s answered something else than a hawt bridge reply at t = %g s",
             bridge.socket_path, (double)SWAP(R_TIME));
        return -1;
    }
    answer->message[MESSAGE_CHARS - 1] = '\0';
    if (answer->fail < 0) {
        fail("%s", answer->message);
        return -1;
    }
    return 0;
}

/* Safe commands: each blade's last pitch towards feather at the largest rate, the last torque held. */
static void safe_commands(float *avrSWAP)
{
    int b = blades_of(avrSWAP);
    float angle = bridge.feather_angle > 0 ? bridge.feather_angle
                  : SWAP(R_MAX_PITCH) > 0 ? SWAP(R_MAX_PITCH) : DEFAULT_FEATHER_ANGLE;
    float rate = bridge.feather_rate > 0 ? bridge.feather_rate
                 : SWAP(R_MAX_PITCH_RATE) > 0 ? SWAP(R_MAX_PITCH_RATE) : DEFAULT_FEATHER_RATE;
    float sum = 0;
    for (int i = 0; i < b; i++) {
        bridge.pitch[i] = fminf(bridge.pitch[i] + rate * SWAP(R_DT), fmaxf(angle, bridge.pitch[i]));
        SWAP(R_DEMANDED_PITCH_1 + i) = bridge.pitch[i];
        sum += bridge.pitch[i];
    }
    SWAP(R_DEMANDED_COLLECTIVE) = sum / b;
    SWAP(R_DEMANDED_TORQUE) = bridge.torque;
}

static void report(int *aviFAIL, const float *avrSWAP, char *avcMSG)
{
    int size = (int)lroundf(SWAP(R_MESSAGE_SIZE));
    *aviFAIL = -1;
    snprintf(avcMSG, size > 0 && size < MESSAGE_CHARS ? size : MESSAGE_CHARS, "%s", bridge.failure);
}

void DISCON(float *avrSWAP, int *aviFAIL, char *accINFILE, char *avcOUTNAME, char *avcMSG)
{
    (void)avcOUTNAME;
    int status = (int)lroundf(SWAP(R_STATUS));
    struct reply answer;
    *aviFAIL = 0;
    if (status == 0) {
        /* a first call: start from the measured pitch and torque, whatever happened before */
        const int pitch_records[MAX_BLADES] = {R_PITCH_1, R_PITCH_2, R_PITCH_3};
        if (bridge.fd >= 0)
            close(bridge.fd);
        bridge.fd = -1;
        bridge.failed = 0;
        bridge.feather_angle = bridge.feather_rate = 0;
        for (int i = 0; i < MAX_BLADES; i++)
            bridge.pitch[i] = SWAP(pitch_records[i]);
        bridge.torque = SWAP(R_GENERATOR_TORQUE);
        if (read_bridge_file(accINFILE) != 0 || connect_bridge() != 0) {
            safe_commands(avrSWAP);
            report(aviFAIL, avrSWAP, avcMSG);
            return;
        }
    }
    if (bridge.failed || bridge.fd < 0) {
        if (!bridge.failed)
            fail("hawt bridge: called with status %d before a first call (status 0)", status);
        safe_commands(avrSWAP);
        report(aviFAIL, avrSWAP, avcMSG);
        return;
    }
    if (exchange(avrSWAP, accINFILE, &answer) != 0) {
        safe_commands(avrSWAP);
        report(aviFAIL, avrSWAP, avcMSG);
        return;
    }
    int b = blades_of(avrSWAP);
    for (int i = 0; i < b; i++) {
        bridge.pitch[i] = answer.pitch[i];
        SWAP(R_DEMANDED_PITCH_1 + i) = answer.pitch[i];
    }
    bridge.torque = answer.torque;
    bridge.feather_angle = answer.feather_angle;
    bridge.feather_rate = answer.feather_rate;
    SWAP(R_DEMANDED_COLLECTIVE) = answer.collective;
    SWAP(R_DEMANDED_TORQUE) = answer.torque;
    SWAP(R_PITCH_OVERRIDE) = 0;
    SWAP(R_TORQUE_OVERRIDE) = 0;
    if (status < 0) {
        close(bridge.fd);
        bridge.fd = -1;
    }
}
