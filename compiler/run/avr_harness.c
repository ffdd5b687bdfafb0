/*
 * avr_harness: run an Intel HEX image in simavr under a line-oriented
 * command script read from stdin.
 *
 *   avr_harness <mcu> <freq_hz> <file.hex>
 *
 * Every line this program prints starts with '@'. simavr's own messages,
 * which libsimavr prints on stdout, are sent to stderr (stdout is moved to
 * a private descriptor first); callers keep only '@' lines anyway.
 * After loading: "@loaded <bytes of flash image>". Commands, one per line:
 *
 *   drive <port> <bit> <0|1>     drive an input pin from outside (the pin is
 *                                declared external, so the firmware's pull-up
 *                                writes do not override it)
 *   watch <port> <bit>           report level changes of that pin (an output's
 *                                PORT bit, or the level driven on an input):
 *                                  @level <cycle> <P><bit> <0|1>   (once)
 *                                  @edge <cycle> <P><bit> <0|1>    (each change)
 *   run <cycles>                 advance the simulation
 *   run_us <microseconds>        advance the simulation
 *   run_to <cycle>               run until the absolute cycle count is reached
 *                                (the last instruction may overshoot by a few cycles)
 *   read <port>                  @port <P> <PORT hex> <DDR hex> <PIN hex>
 *   adc <channel> <millivolts>   set an ADC input voltage
 *   uart <0|1>                   the UART the other uart lines are about (UART0
 *                                until told: the ATmega32U4 and AT90USB647 have only UART1)
 *   uart_in <byte>               queue a byte into that UART's receiver
 *                                (its transmitter: @uart <cycle> <byte>)
 *   eeprom_read <addr> <len>     @eeprom <hex bytes>
 *   peek <addr> [len]            data memory (registers, I/O, RAM; data-space address):
 *                                @peek <addr decimal> <hex bytes>
 *   reset                        reset the MCU (EEPROM kept)  -> @reset <cycle>
 *   cycles                       @cycles <n>
 *   quit                         -> @bye <cycle>
 *
 * Errors print "@error <message>"; a crashed/stopped core prints
 * "@state <cycle> <state>" and further "run" commands do nothing.
 * AVR_HARNESS_LOG=<0..5> in the environment turns simavr's log on (stderr).
 *
 * Build: gcc -O2 -I/usr/include/simavr avr_harness.c -o avr_harness -lsimavr
 * (libsimavr.so already pulls in libelf; Debian ships no -lelf link name
 * without libelf-dev).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <ctype.h>
#include <unistd.h>

#include "sim_avr.h"
#include "sim_hex.h"
#include "sim_io.h"
#include "sim_irq.h"
#include "avr_ioport.h"
#include "avr_adc.h"
#include "avr_uart.h"
#include "avr_eeprom.h"

#define NPORTS 12 /* 'A'..'L' */

static avr_t *avr;
static FILE *out; /* our result lines; the library's stdout goes to stderr */
static int done_state; /* nonzero once the core stopped */

/* external drive state, per port */
static uint8_t ext_mask[NPORTS], ext_value[NPORTS];
/* watched pins: last reported level, -1 = not watched */
static int watch_last[NPORTS][8];

/* the UART the harness feeds and listens to */
static avr_irq_t *uart_tx, *uart_rx;

static void uart_out(struct avr_irq_t *irq, uint32_t value, void *param);

/* report a UART's transmitted bytes, feed its receiver; no stdio, no sleeping */
static void hook_uart(char n)
{
	if (uart_tx)
		avr_irq_unregister_notify(uart_tx, uart_out, NULL);
	uint32_t flags = 0;
	if (avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS(n), &flags) == 0) {
		flags &= ~(uint32_t)(AVR_UART_FLAG_POLL_SLEEP | AVR_UART_FLAG_STDIO);
		avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS(n), &flags);
	}
	uart_tx = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ(n), UART_IRQ_OUTPUT);
	uart_rx = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ(n), UART_IRQ_INPUT);
	if (uart_tx)
		avr_irq_register_notify(uart_tx, uart_out, NULL);
}

static int port_index(char c)
{
	c = (char)toupper((unsigned char)c);
	if (c < 'A' || c >= 'A' + NPORTS)
		return -1;
	return c - 'A';
}

static void no_sleep(avr_t *a, avr_cycle_count_t how_long)
{
	(void)a;
	(void)how_long;
}

static void pin_changed(struct avr_irq_t *irq, uint32_t value, void *param)
{
	(void)irq;
	intptr_t key = (intptr_t)param;
	int pi = (int)(key >> 3), bit = (int)(key & 7);
	int v = (value & 0xff) ? 1 : 0;
	if (watch_last[pi][bit] < 0 || watch_last[pi][bit] == v)
		return;
	watch_last[pi][bit] = v;
	fprintf(out, "@edge %llu %c%d %d\n", (unsigned long long)avr->cycle, 'A' + pi, bit, v);
}

static void uart_out(struct avr_irq_t *irq, uint32_t value, void *param)
{
	(void)irq;
	(void)param;
	fprintf(out, "@uart %llu %u\n", (unsigned long long)avr->cycle, value & 0xff);
}

static int get_state(int pi, avr_ioport_state_t *st)
{
	return avr_ioctl(avr, AVR_IOCTL_IOPORT_GETSTATE('A' + pi), st);
}

/* Electrical level of a pin: PORT bit for an output, else the PIN bit
 * (external drive or pull-up already folded into PIN by simavr). */
static int pin_level(int pi, int bit)
{
	avr_ioport_state_t st;
	if (get_state(pi, &st) != 0)
		return 0;
	if ((st.ddr >> bit) & 1)
		return (st.port >> bit) & 1;
	if ((ext_mask[pi] >> bit) & 1)
		return (ext_value[pi] >> bit) & 1;
	return (st.pin >> bit) & 1;
}

static void apply_drive(int pi, int bit, int v, int force)
{
	avr_ioport_external_t ext = {
		.name = 'A' + pi,
		.mask = ext_mask[pi],
		.value = ext_value[pi],
	};
	avr_ioctl(avr, AVR_IOCTL_IOPORT_SET_EXTERNAL('A' + pi), &ext);
	avr_irq_t *irq = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('A' + pi), bit);
	if (!irq)
		return;
	if (force)
		irq->value = v ? 0 : 1; /* defeat IRQ_FLAG_FILTERED so PIN gets rewritten */
	avr_raise_irq(irq, v);
}

static uint8_t *eeprom_base(uint32_t *size)
{
	avr_eeprom_desc_t d = { .ee = NULL, .offset = 0, .size = 1 };
	avr_ioctl(avr, AVR_IOCTL_EEPROM_GET, &d);
	*size = avr->e2end + 1;
	return d.ee;
}

static int load_hex(const char *fname)
{
	ihex_chunk_p chunks = NULL;
	int n = read_ihex_chunks(fname, &chunks);
	if (n <= 0) {
		fprintf(out, "@error cannot read hex file %s\n", fname);
		return -1;
	}
	uint32_t flash_top = 0;
	for (int i = 0; i < n; i++) {
		uint32_t base = chunks[i].baseaddr, size = chunks[i].size;
		if (base >= 0x810000) { /* EEPROM segment (avr-objcopy convention) */
			uint32_t esize;
			uint8_t *ee = eeprom_base(&esize);
			base -= 0x810000;
			if (!ee || base + size > esize) {
				fprintf(out, "@error eeprom chunk out of range\n");
				return -1;
			}
			memcpy(ee + base, chunks[i].data, size);
		} else {
			if (base + size > avr->flashend + 1) {
				fprintf(out, "@error flash chunk 0x%x+%u beyond flash end 0x%x\n",
				       base, size, avr->flashend);
				return -1;
			}
			memcpy(avr->flash + base, chunks[i].data, size);
			if (base + size > flash_top)
				flash_top = base + size;
		}
	}
	free_ihex_chunks(chunks);
	avr->codeend = avr->flashend;
	fprintf(out, "@loaded %u\n", flash_top);
	return 0;
}

static void run_cycles(unsigned long long n)
{
	if (done_state)
		return;
	avr_cycle_count_t target = avr->cycle + n;
	while (avr->cycle < target) {
		int st = avr_run(avr);
		if (st == cpu_Done || st == cpu_Crashed) {
			done_state = st;
			fprintf(out, "@state %llu %s\n", (unsigned long long)avr->cycle,
			       st == cpu_Done ? "done" : "crashed");
			return;
		}
	}
}

int main(int argc, char **argv)
{
	if (argc != 4) {
		fprintf(stderr, "usage: %s <mcu> <freq_hz> <file.hex>\n", argv[0]);
		return 2;
	}
	/* Keep fd 1 for our own '@' lines and send simavr's printf noise to
	 * stderr, so that a library message without a newline cannot corrupt a
	 * result line. */
	int res_fd = dup(1);
	out = res_fd >= 0 ? fdopen(res_fd, "w") : NULL;
	if (out)
		dup2(2, 1);
	else
		out = stdout;
	setvbuf(out, NULL, _IOLBF, 0);
	avr = avr_make_mcu_by_name(argv[1]);
	if (!avr) {
		fprintf(out, "@error unknown mcu %s\n", argv[1]);
		return 2;
	}
	avr_init(avr);
	/* AVR_HARNESS_LOG=<0..5> turns simavr's own log on (it goes to stderr) */
	avr->log = getenv("AVR_HARNESS_LOG") ? atoi(getenv("AVR_HARNESS_LOG")) : LOG_NONE;
	avr->frequency = (uint32_t)strtoul(argv[2], NULL, 10);
	avr->sleep = no_sleep;
	avr->vcc = avr->avcc = avr->aref = 5000;
	if (load_hex(argv[3]) != 0)
		return 1;

	for (int i = 0; i < NPORTS; i++)
		for (int b = 0; b < 8; b++)
			watch_last[i][b] = -1;

	hook_uart('0');

	char line[512];
	while (fgets(line, sizeof line, stdin)) {
		char cmd[32] = "", a1[64] = "", a2[64] = "", a3[64] = "";
		int na = sscanf(line, "%31s %63s %63s %63s", cmd, a1, a2, a3);
		if (na <= 0 || cmd[0] == '#')
			continue;
		if (!strcmp(cmd, "drive") && na == 4) {
			int pi = port_index(a1[0]), bit = atoi(a2), v = atoi(a3) ? 1 : 0;
			if (pi < 0 || bit < 0 || bit > 7 || get_state(pi, &(avr_ioport_state_t){0}) != 0) {
				fprintf(out, "@error no pin %s%s\n", a1, a2);
				continue;
			}
			ext_mask[pi] |= 1 << bit;
			ext_value[pi] = (ext_value[pi] & ~(1 << bit)) | (v << bit);
			apply_drive(pi, bit, v, 0);
		} else if (!strcmp(cmd, "watch") && na == 3) {
			int pi = port_index(a1[0]), bit = atoi(a2);
			avr_irq_t *irq = pi < 0 || bit < 0 || bit > 7 ? NULL :
				avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('A' + pi), bit);
			if (!irq) {
				fprintf(out, "@error no pin %s%s\n", a1, a2);
				continue;
			}
			if (watch_last[pi][bit] < 0)
				avr_irq_register_notify(irq, pin_changed, (void *)(intptr_t)(pi * 8 + bit));
			watch_last[pi][bit] = pin_level(pi, bit);
			fprintf(out, "@level %llu %c%d %d\n", (unsigned long long)avr->cycle, 'A' + pi, bit,
			       watch_last[pi][bit]);
		} else if (!strcmp(cmd, "run") && na == 2) {
			run_cycles(strtoull(a1, NULL, 10));
		} else if (!strcmp(cmd, "run_to") && na == 2) {
			unsigned long long t = strtoull(a1, NULL, 10);
			if (t > avr->cycle)
				run_cycles(t - avr->cycle);
		} else if (!strcmp(cmd, "run_us") && na == 2) {
			double us = strtod(a1, NULL);
			run_cycles((unsigned long long)(us * (double)avr->frequency / 1e6 + 0.5));
		} else if (!strcmp(cmd, "read") && na == 2) {
			int pi = port_index(a1[0]);
			avr_ioport_state_t st;
			if (pi < 0 || get_state(pi, &st) != 0) {
				fprintf(out, "@error no port %s\n", a1);
				continue;
			}
			fprintf(out, "@port %c %02x %02x %02x\n", 'A' + pi, (unsigned)st.port,
			       (unsigned)st.ddr, (unsigned)st.pin);
		} else if (!strcmp(cmd, "adc") && na == 3) {
			int ch = atoi(a1);
			avr_irq_t *irq = ch < 0 || ch > 15 ? NULL :
				avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_ADC0 + ch);
			if (!irq) {
				fprintf(out, "@error no adc channel %s\n", a1);
				continue;
			}
			avr_raise_irq(irq, (uint32_t)atoi(a2));
		} else if (!strcmp(cmd, "uart") && na == 2 && (a1[0] == '0' || a1[0] == '1') && !a1[1]) {
			hook_uart(a1[0]);
			if (!uart_rx)
				fprintf(out, "@error no uart%c\n", a1[0]);
		} else if (!strcmp(cmd, "uart_in") && na == 2) {
			if (!uart_rx) {
				fprintf(out, "@error no uart\n");
				continue;
			}
			avr_raise_irq(uart_rx, (uint32_t)strtoul(a1, NULL, 0) & 0xff);
		} else if (!strcmp(cmd, "eeprom_read") && na == 3) {
			uint32_t esize, addr = strtoul(a1, NULL, 0), len = strtoul(a2, NULL, 0);
			uint8_t *ee = eeprom_base(&esize);
			if (!ee || addr + len > esize) {
				fprintf(out, "@error eeprom range\n");
				continue;
			}
			fprintf(out, "@eeprom");
			for (uint32_t i = 0; i < len; i++)
				fprintf(out, " %02x", ee[addr + i]);
			fprintf(out, "\n");
		} else if (!strcmp(cmd, "peek") && (na == 2 || na == 3)) {
			uint32_t addr = strtoul(a1, NULL, 0), len = na == 3 ? strtoul(a2, NULL, 0) : 1;
			if (addr + len > (uint32_t)avr->ramend + 1) {
				fprintf(out, "@error peek range\n");
				continue;
			}
			fprintf(out, "@peek %u", addr);
			for (uint32_t i = 0; i < len; i++)
				fprintf(out, " %02x", avr->data[addr + i]);
			fprintf(out, "\n");
		} else if (!strcmp(cmd, "reset") && na == 1) {
			if (done_state == cpu_Done) { /* simavr freed the core */
				fprintf(out, "@error cannot reset: core terminated\n");
				continue;
			}
			avr_reset(avr);
			avr->state = cpu_Running;
			done_state = 0;
			/* avr_reset zeroes the I/O registers: re-apply external drives */
			for (int pi = 0; pi < NPORTS; pi++)
				for (int b = 0; b < 8; b++)
					if ((ext_mask[pi] >> b) & 1)
						apply_drive(pi, b, (ext_value[pi] >> b) & 1, 1);
			fprintf(out, "@reset %llu\n", (unsigned long long)avr->cycle);
		} else if (!strcmp(cmd, "cycles") && na == 1) {
			fprintf(out, "@cycles %llu\n", (unsigned long long)avr->cycle);
		} else if (!strcmp(cmd, "quit")) {
			break;
		} else {
			fprintf(out, "@error bad command: %s", line);
			if (!strchr(line, '\n'))
				fprintf(out, "\n");
		}
	}
	fprintf(out, "@bye %llu\n", (unsigned long long)avr->cycle);
	return 0;
}
