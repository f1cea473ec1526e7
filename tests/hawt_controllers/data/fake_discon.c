/* A fake Bladed-style DISCON library for tests of hawt_controllers.discon.library.
 *
 * The input file (accINFILE) holds two lines: the path of a log file, and the call number (0 = first) at
 * which to fail with aviFAIL = -1 and the message "fake failure" (-1: never). Each call appends one line to
 * the log: the records 1..130 it received, separated by spaces. It returns fixed demands: pitch 0.01, 0.02,
 * 0.03 rad (records 42-44), collective 0.05 rad (45), torque 12345 N*m (47), pitch override 0 (55).
 * Like ROSCO, it refuses a second first call (status 0) in one loaded image. Build with
 * -DENTRY=<name> to export another name than DISCON.
 */
#include <stdio.h>
#include <string.h>

#ifndef ENTRY
#define ENTRY DISCON
#endif

static int started = 0;
static int calls = 0;

static void fail(int *aviFAIL, char *avcMSG, int size, const char *text) {
    *aviFAIL = -1;
    strncpy(avcMSG, text, size - 1);
    avcMSG[size - 1] = '\0';
}

void ENTRY(float *avrSWAP, int *aviFAIL, char *accINFILE, char *avcOUTNAME, char *avcMSG) {
    char log_path[1024] = "";
    int fail_at = -1;
    int message_size = (int)avrSWAP[48];
    FILE *in = fopen(accINFILE, "r");
    (void)avcOUTNAME;
    *aviFAIL = 0;
    if (in == NULL) {
        fail(aviFAIL, avcMSG, message_size, "cannot open the input file");
        return;
    }
    if (fscanf(in, "%1023s %d", log_path, &fail_at) < 1) {
        fclose(in);
        fail(aviFAIL, avcMSG, message_size, "no log path in the input file");
        return;
    }
    fclose(in);
    if ((int)avrSWAP[0] == 0) {
        if (started) {
            fail(aviFAIL, avcMSG, message_size, "already loaded in this image");
            return;
        }
        started = 1;
    }
    FILE *log = fopen(log_path, "a");
    for (int record = 1; record <= 130 && log != NULL; record++) {
        fprintf(log, record < 130 ? "%.9g " : "%.9g\n", avrSWAP[record - 1]);
    }
    if (log != NULL) {
        fclose(log);
    }
    if (calls++ == fail_at) {
        fail(aviFAIL, avcMSG, message_size, "fake failure");
        return;
    }
    avrSWAP[41] = 0.01f;
    avrSWAP[42] = 0.02f;
    avrSWAP[43] = 0.03f;
    avrSWAP[44] = 0.05f;
    avrSWAP[46] = 12345.0f;
    avrSWAP[54] = 0.0f;
}
