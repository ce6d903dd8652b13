/*
 * Subscribes to a softnc instance's setpoints and status with the iceoryx2 C bindings
 * (0.10.0, the version softnc is built with), as a HIL rig in C would:
 *
 *     ./softnc_subscribe INSTANCE
 *
 * It waits for INSTANCE/setpoints, counts every setpoint, reports gaps in the sequence
 * numbers (lost samples) and, when the kernel has gone, prints the count and the last
 * position. docs/interfaces.md explains the services, the prefix and the ABI attribute.
 *
 * Not built by softnc's tests: the C bindings are built from the iceoryx2 source and no
 * machine of this project has them (compiled once by hand against the bindings' header of
 * shortly before 0.10.0; never linked or run against softnc). The payload header beside it
 * is compiled and checked by tests/clients.rs.
 */
#define _POSIX_C_SOURCE 200809L /* nanosleep */

#include "iox2/iceoryx2.h"
#include "softnc_ipc.h"

#include <stdalign.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

struct stream {
    iox2_port_factory_pub_sub_h service;
    iox2_subscriber_h subscriber;
    uint64_t count, last_seq, gaps, lost;
};

static void sleep_ms(long ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

/* Opens INSTANCE/NAME once softnc has created it (never creates it), requiring the ABI this
 * header describes: a softnc of another protocol is refused here. */
static int open_stream(iox2_node_h* node, const char* instance, const char* name,
                       const char* type_name, size_t size, size_t align, struct stream* s) {
    char full[128];
    snprintf(full, sizeof full, "%s/%s", instance, name);
    iox2_service_name_h service_name = NULL;
    if (iox2_service_name_new(NULL, full, strlen(full), &service_name) != IOX2_OK) {
        return -1;
    }
    iox2_attribute_verifier_h abi = NULL;
    iox2_attribute_verifier_new(NULL, &abi);
    iox2_attribute_verifier_require(&abi, SOFTNC_ABI_KEY, SOFTNC_ABI);
    int ret = -1;
    for (int tries = 0; tries < 1500; tries++) { /* 30 s */
        iox2_service_builder_h builder =
            iox2_node_service_builder(node, NULL, iox2_cast_service_name_ptr(service_name));
        iox2_service_builder_pub_sub_h pub_sub = iox2_service_builder_pub_sub(builder);
        iox2_service_builder_pub_sub_set_payload_type_details(
            &pub_sub, iox2_type_variant_e_FIXED_SIZE, type_name, strlen(type_name), size, align);
        /* softnc's payloads have no user header: Rust's (), size 0, alignment 1. */
        iox2_service_builder_pub_sub_set_user_header_type_details(
            &pub_sub, iox2_type_variant_e_FIXED_SIZE, "()", 2, 0, 1);
        ret = iox2_service_builder_pub_sub_open_with_attributes(pub_sub, &abi, NULL, &s->service);
        if (ret == IOX2_OK) {
            break;
        }
        if (ret != iox2_pub_sub_open_or_create_error_e_O_DOES_NOT_EXIST) {
            fprintf(stderr, "%s: cannot open: %s\n", full,
                    iox2_pub_sub_open_or_create_error_string(ret));
            break;
        }
        sleep_ms(20);
    }
    iox2_attribute_verifier_drop(abi);
    iox2_service_name_drop(service_name);
    if (ret != IOX2_OK) {
        return -1;
    }
    iox2_port_factory_subscriber_builder_h sb =
        iox2_port_factory_pub_sub_subscriber_builder(&s->service, NULL);
    return iox2_port_factory_subscriber_builder_create(sb, NULL, &s->subscriber) == IOX2_OK
               ? 0
               : -1;
}

/* Takes every sample that arrived; copies the payload (a subscriber may hold at most 2). */
static int drain(struct stream* s, void* last, size_t size) {
    int n = 0;
    for (;;) {
        iox2_sample_h sample = NULL;
        if (iox2_subscriber_receive(&s->subscriber, NULL, &sample) != IOX2_OK || !sample) {
            return n;
        }
        const void* payload = NULL;
        iox2_sample_payload(&sample, &payload, NULL);
        memcpy(last, payload, size);
        iox2_sample_drop(sample);
        uint64_t seq = *(const uint64_t*) last; /* seq is the first field of both streams */
        if (s->count > 0 && seq > s->last_seq + 1) {
            s->gaps++;
            s->lost += seq - s->last_seq - 1;
        }
        s->last_seq = seq;
        s->count++;
        n++;
    }
}

int main(int argc, char** argv) {
    const char* instance = argc > 1 ? argv[1] : "softnc";
    char prefix[80];
    snprintf(prefix, sizeof prefix, "softnc_%s_", instance);

    iox2_config_h config = NULL;
    iox2_config_default(NULL, &config);
    iox2_config_global_set_prefix(&config, prefix);
    iox2_node_name_h node_name = NULL;
    iox2_node_name_new(NULL, "c-subscriber", strlen("c-subscriber"), &node_name);
    iox2_node_builder_h node_builder = iox2_node_builder_new(NULL);
    iox2_node_builder_set_config(&node_builder, &config);
    iox2_node_builder_set_name(&node_builder, iox2_cast_node_name_ptr(node_name));
    iox2_node_h node = NULL;
    if (iox2_node_builder_create(node_builder, NULL, iox2_service_type_e_IPC, &node) != IOX2_OK) {
        fprintf(stderr, "cannot create the node\n");
        return 2;
    }

    struct stream sp = {0}, st = {0};
    struct softnc_SetpointMsg last_sp = {0};
    struct softnc_KernelStatus last_st = {0};
    if (open_stream(&node, instance, "setpoints", "softnc::SetpointMsg",
                    sizeof(struct softnc_SetpointMsg), alignof(struct softnc_SetpointMsg), &sp) ||
        open_stream(&node, instance, "status", "softnc::KernelStatus",
                    sizeof(struct softnc_KernelStatus), alignof(struct softnc_KernelStatus), &st)) {
        return 2;
    }
    for (;;) {
        int got = drain(&sp, &last_sp, sizeof last_sp) + drain(&st, &last_st, sizeof last_st);
        if (sp.count > 0 && iox2_port_factory_pub_sub_dynamic_config_number_of_publishers(&sp.service) == 0) {
            drain(&sp, &last_sp, sizeof last_sp); /* the kernel has gone */
            break;
        }
        if (!got) {
            sleep_ms(1);
        }
    }
    printf("%llu setpoints, %llu lost in %llu gaps; last:", (unsigned long long) sp.count,
           (unsigned long long) sp.lost, (unsigned long long) sp.gaps);
    for (int i = 0; i < last_sp.axes && i < SOFTNC_MAX_AXES; i++) {
        char name = i < last_st.axes.count ? (char) last_st.axes.names[i] : '?';
        printf(" %c%.4f", name, last_sp.pos[i]);
    }
    printf("\n");

    iox2_subscriber_drop(st.subscriber);
    iox2_subscriber_drop(sp.subscriber);
    iox2_port_factory_pub_sub_drop(st.service);
    iox2_port_factory_pub_sub_drop(sp.service);
    iox2_node_drop(node);
    iox2_node_name_drop(node_name);
    iox2_config_drop(config);
    return 0;
}
